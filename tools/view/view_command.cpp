// dynweigh view: a live window on a running scene (SDL2 + OpenGL), as the thesis watched its models
// run: the silo, the valve, the falling stream, the pile, and the force on the load cell scrolling
// by with the valve marker. The plant runs open loop under the keys (or --open-at/--close-at).
#define SDL_MAIN_HANDLED
#include <SDL.h>
#include <SDL_opengl.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "finite_range.hpp"
#include "force_trace.hpp"
#include "output_file.hpp"
#include "png_writer.hpp"
#include "scene_drawing.hpp"
#include "view_commands.hpp"
#include "command_line.hpp"

namespace dynweigh::tools {
namespace {

constexpr double kJiffyS = 0.010;  // the plant advances in the indicator's jiffies

struct Arguments {
  std::string scene = "default";
  std::uint64_t seed = 1;
  double fps = 50.0;
  double speed = 1.0;
  double open_at_s = -1.0;
  double close_at_s = -1.0;
  int frames = 0;
  std::string screenshot;
  int width = 1100, height = 600;
};

constexpr const char* kNoDisplay =
    "no display to open a window on: run it in a desktop session (DISPLAY or WAYLAND_DISPLAY set), or headless "
    "with --frames N [--screenshot F.png]";

bool has_display_environment() {
  return std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY") || std::getenv("SDL_VIDEODRIVER");
}

// SDL falls back to these when it finds no display: they draw, but nobody sees a window.
bool headless_driver(const char* name) {
  return name && (std::strcmp(name, "offscreen") == 0 || std::strcmp(name, "dummy") == 0);
}

// SDL and its window and GL context, released in the right order. An interactive window without a
// display is refused; a --frames run without one renders offscreen.
class Window {
 public:
  Window(const std::string& title, int width, int height, bool interactive) {
    if (!has_display_environment()) {
      if (interactive) throw std::runtime_error(kNoDisplay);
      SDL_SetHint(SDL_HINT_VIDEODRIVER, "offscreen");  // no probing of X11 and Wayland, no noise
    } else if (!std::getenv("WAYLAND_DISPLAY")) {
      SDL_SetHint(SDL_HINT_VIDEODRIVER, "x11");  // a DISPLAY that does not answer fails in one line
    }
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
      throw std::runtime_error(std::string("cannot open the display (") + SDL_GetError() + "); headless: unset DISPLAY, give --frames N");
    }
    if (interactive && headless_driver(SDL_GetCurrentVideoDriver())) {
      SDL_Quit();
      throw std::runtime_error(kNoDisplay);
    }
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    window_ = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, width, height,
                               SDL_WINDOW_OPENGL | SDL_WINDOW_SHOWN);
    if (!window_) fail("cannot open a window");
    context_ = SDL_GL_CreateContext(window_);
    if (!context_) fail("no OpenGL context");
  }
  ~Window() {
    if (context_) SDL_GL_DeleteContext(context_);
    if (window_) SDL_DestroyWindow(window_);
    SDL_Quit();
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
  SDL_Window* get() const { return window_; }

 private:
  [[noreturn]] void fail(const char* what) {
    const std::string reason = std::string(what) + ": " + SDL_GetError();
    if (window_) SDL_DestroyWindow(window_);
    SDL_Quit();
    window_ = nullptr;
    throw std::runtime_error(reason);
  }
  SDL_Window* window_ = nullptr;
  SDL_GLContext context_ = nullptr;
};

void save_screenshot(const std::string& path, int width, int height) {
  std::vector<std::uint8_t> bottom_up(std::size_t(width) * std::size_t(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  std::vector<std::uint8_t> top_down(bottom_up.size());
  const std::size_t row = std::size_t(width) * 3;
  for (int y = 0; y < height; ++y) {
    std::copy_n(bottom_up.begin() + std::ptrdiff_t(row * std::size_t(height - 1 - y)), row,
                top_down.begin() + std::ptrdiff_t(row * std::size_t(y)));
  }
  write_png(path, width, height, top_down);
}

const char* valve_name(sim::ValveCommand c) {
  return c == sim::ValveCommand::open ? "open" : c == sim::ValveCommand::half ? "half" : "closed";
}

int run(const Arguments& a) {
  const auto scene = sim::scene_by_name(a.scene);
  if (!scene) throw std::runtime_error("unknown scene '" + a.scene + "'");
  auto plant = std::make_unique<sim::Plant>(*scene, a.seed);
  Window window("dynweigh view: " + a.scene, a.width, a.height, a.frames == 0);
  SDL_GL_SetSwapInterval(a.frames > 0 ? 0 : 1);

  ForceTrace trace;
  StreamTimes stream;
  sim::ValveCommand valve = sim::ValveCommand::closed;
  const auto command = [&](sim::ValveCommand c) {
    if (c == valve) return;
    if (c != sim::ValveCommand::closed && valve == sim::ValveCommand::closed) stream.opened_s = plant->truth().time_s;
    if (c == sim::ValveCommand::closed) stream.closed_s = plant->truth().time_s;
    valve = c;
    plant->command_valve(c);
  };
  const auto step_jiffy = [&] {
    const double t = plant->truth().time_s;
    if (a.open_at_s >= 0 && t >= a.open_at_s && t < a.open_at_s + kJiffyS / 2) command(sim::ValveCommand::open);
    if (a.close_at_s >= 0 && t >= a.close_at_s && t < a.close_at_s + kJiffyS / 2) command(sim::ValveCommand::closed);
    plant->advance(kJiffyS);
    trace.add(plant->truth().time_s, plant->truth().force_n, int(valve));
  };

  const double jiffies_per_frame = a.speed / a.fps / kJiffyS;
  double owed_jiffies = 0.0;
  bool paused = false, running = true;
  int frames = 0;
  const auto start = std::chrono::steady_clock::now();
  auto next_frame = start;
  auto last_title = start;
  while (running) {
    for (SDL_Event e; SDL_PollEvent(&e);) {
      if (e.type == SDL_QUIT) running = false;
      if (e.type != SDL_KEYDOWN) continue;
      switch (e.key.keysym.sym) {
        case SDLK_ESCAPE:
        case SDLK_q: running = false; break;
        case SDLK_SPACE:
        case SDLK_p: paused = !paused; break;
        case SDLK_s:
        case SDLK_RIGHT: if (paused) step_jiffy(); break;
        case SDLK_o: command(sim::ValveCommand::open); break;
        case SDLK_h: command(sim::ValveCommand::half); break;
        case SDLK_c: command(sim::ValveCommand::closed); break;
        case SDLK_r:
          plant = std::make_unique<sim::Plant>(*scene, a.seed);
          trace.clear();
          stream = {};
          valve = sim::ValveCommand::closed;
          break;
        default: break;
      }
    }
    if (!paused) {
      owed_jiffies += jiffies_per_frame;
      for (; owed_jiffies >= 1.0; owed_jiffies -= 1.0) step_jiffy();
    }

    int w = a.width, h = a.height;
    SDL_GL_GetDrawableSize(window.get(), &w, &h);
    glViewport(0, 0, w, h);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, w, 0, h, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glClearColor(0.04f, 0.05f, 0.06f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    const float fw = float(w), fh = float(h);
    draw_plant(*plant, stream, Rect{8.0f, 8.0f, 0.32f * fw - 12.0f, fh - 16.0f});
    trace.draw(Rect{0.32f * fw + 4.0f, 8.0f, 0.68f * fw - 12.0f, fh - 16.0f});
    ++frames;
    const bool last = a.frames > 0 && frames >= a.frames;
    if (last && !a.screenshot.empty()) save_screenshot(a.screenshot, w, h);
    SDL_GL_SwapWindow(window.get());
    if (last) break;

    const auto now = std::chrono::steady_clock::now();
    if (now - last_title > std::chrono::milliseconds(250)) {
      last_title = now;
      char title[200];
      std::snprintf(title, sizeof title, "dynweigh view: %s  t=%.2f s  force=%.1f N  static=%.3f kg  valve=%s%s   "
                    "[space pause, s step, o/h/c valve, r reset, q quit]",
                    a.scene.c_str(), plant->truth().time_s, plant->truth().force_n, plant->truth().static_kg,
                    valve_name(valve), paused ? "  PAUSED" : "");
      SDL_SetWindowTitle(window.get(), title);
    }
    if (a.frames == 0) {  // interactive: hold the frame rate; a test renders as fast as it can
      next_frame += std::chrono::microseconds(long(1e6 / a.fps));
      const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next_frame - std::chrono::steady_clock::now());
      if (wait.count() > 0) SDL_Delay(Uint32(wait.count()));
      else next_frame = std::chrono::steady_clock::now();
    }
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("frames=%d\nsim_s=%.2f\nfps=%.1f\nfinal_static_kg=%.6f\n", frames, plant->truth().time_s,
              wall_s > 0 ? frames / wall_s : 0.0, plant->truth().static_kg);
  if (!a.screenshot.empty()) std::printf("screenshot=%s\n", a.screenshot.c_str());
  return 0;
}

}  // namespace

int run_view_command(int argc, char** argv) {
  Arguments a;
  CLI::App app{"dynweigh view: a live window on a running scene: the silo, the valve, the falling stream, the pile\n"
               "and the force on the load cell scrolling by with the valve marker (SDL2 + OpenGL).\n"
               "Keys: space or p pause, s or right arrow one jiffy while paused, o open, h half, c close the\n"
               "valve, r restart, q or Esc quit. The window title shows time, force, static mass, valve.\n"
               "Without a display (neither DISPLAY nor WAYLAND_DISPLAY set) it exits 1 unless --frames is given:\n"
               "then it renders offscreen."};
  app.add_option("--scene", a.scene, "scene name or .json file")->capture_default_str();
  app.add_option("--seed", a.seed, "seed of the plant's disturbances")->capture_default_str();
  app.add_option("--fps", a.fps, "frames per second")->capture_default_str()->check(FiniteRange(1.0, 240.0));
  app.add_option("--speed", a.speed, "simulated seconds per wall second")->capture_default_str()->check(FiniteRange(0.01, 100.0));
  app.add_option("--open-at", a.open_at_s, "open the valve at this simulated time, s")->check(FiniteRange(0.0, 1e7));
  app.add_option("--close-at", a.close_at_s, "close the valve at this simulated time, s")->check(FiniteRange(0.0, 1e7));
  app.add_option("--frames", a.frames, "render this many frames (each --speed/--fps of simulated time) as fast as "
                 "possible, then exit; runs without a display too")->check(CLI::Range(1, 1000000));
  app.add_option("--screenshot", a.screenshot, "with --frames: save the last frame as this .png file");
  app.add_option("--width", a.width, "window width, pixels")->capture_default_str()->check(CLI::Range(200, 4096));
  app.add_option("--height", a.height, "window height, pixels")->capture_default_str()->check(CLI::Range(150, 4096));
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh view")) return *exit_status;
  if (!a.screenshot.empty() && a.frames == 0) {
    std::fprintf(stderr, "dynweigh view: --screenshot needs --frames N\n");
    return 2;
  }
  bool created = false;
  try {
    if (!a.screenshot.empty()) {
      require_extension(a.screenshot, "png", "--screenshot");
      created = check_writable(a.screenshot);  // before the window and the frames, not after them
    }
    return run(a);
  } catch (const std::exception& e) {
    if (created) std::remove(a.screenshot.c_str());  // no empty picture left behind
    std::fprintf(stderr, "dynweigh view: %s\n", e.what());
    return 1;
  }
}

}  // namespace dynweigh::tools
