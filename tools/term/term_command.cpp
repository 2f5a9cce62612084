// dynweigh term: talk to an indicator's console on a serial device or pty (docs/console.md).
// Interactive on a terminal (own line editing and history); with --send, or with commands piped
// to stdin, it sends each line once the previous one was answered (OK or ERR), as a person would,
// and can capture `readtestdata` records into a CSV.
#include <CLI/CLI.hpp>

#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "line_editor.hpp"
#include "serial_port.hpp"
#include "term_commands.hpp"
#include "command_line.hpp"

namespace dynweigh::tools {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kBusyRetryEvery = std::chrono::milliseconds(100);

struct Arguments {
  std::string device;
  unsigned baud = 115200;
  std::vector<std::string> send;
  std::string out;
  double timeout_s = 60.0;
  bool no_retry = false;
  bool quiet = false;
};

bool is_answer(const std::string& line) { return line == "OK" || line.rfind("ERR ", 0) == 0 || line == "ERR"; }

// `<jiffy> <raw> <filtered> <marker>`: a readtestdata record.
bool is_record(const std::string& line, long long (&fields)[4]) {
  std::istringstream in(line);
  for (auto& f : fields) {
    if (!(in >> f)) return false;
  }
  std::string rest;
  return !(in >> rest);
}

// Splits the device's byte stream into lines (LF or CR LF).
class LineSplitter {
 public:
  template <typename OnLine>
  void feed(const char* data, std::size_t n, OnLine&& on_line) {
    for (std::size_t i = 0; i < n; ++i) {
      if (data[i] == '\n') {
        if (!partial_.empty() && partial_.back() == '\r') partial_.pop_back();
        on_line(partial_);
        partial_.clear();
      } else {
        partial_.push_back(data[i]);
      }
    }
  }
  const std::string& partial() const { return partial_; }
  std::string take_partial() { return std::exchange(partial_, {}); }

 private:
  std::string partial_;
};

class RecordCsv {
 public:
  explicit RecordCsv(const std::string& path) : file_(std::fopen(path.c_str(), "w")) {
    if (!file_) throw std::runtime_error("cannot write " + path);
    std::fprintf(file_, "jiffy,raw,filtered,marker\n");
  }
  ~RecordCsv() { std::fclose(file_); }
  bool take(const std::string& line) {
    long long f[4];
    if (!is_record(line, f)) return false;
    std::fprintf(file_, "%lld,%lld,%lld,%lld\n", f[0], f[1], f[2], f[3]);
    ++records_;
    return true;
  }
  std::size_t records() const { return records_; }

 private:
  std::FILE* file_;
  std::size_t records_ = 0;
};

// ------------------------------------------------------------------------------ non-interactive
struct Exchange {
  std::string answer;  // OK or ERR ...
};

// Sends `command` and waits for its answer; lines before it go to `on_line`. `ERR 3 busy` is
// retried every 100 ms until the deadline unless `retry_busy` is false.
template <typename OnLine>
Exchange send_and_wait(SerialPort& port, const std::string& command, double timeout_s, bool retry_busy, OnLine&& on_line) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  LineSplitter lines;
  Exchange exchange;
  for (;;) {
    port.write(command + "\n");
    exchange.answer.clear();
    while (exchange.answer.empty()) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) {
        throw std::runtime_error("no OK or ERR within " + std::to_string(int(timeout_s)) + " s after '" + command + "'");
      }
      char buffer[4096];
      const std::size_t n = port.read(buffer, sizeof buffer, int(std::min<long long>(left, 200)));
      lines.feed(buffer, n, [&](const std::string& line) {
        if (!exchange.answer.empty()) return;  // the rest belongs to nobody we asked
        if (is_answer(line)) {
          exchange.answer = line;
        } else if (!line.empty()) {
          on_line(line);
        }
      });
    }
    if (!(retry_busy && exchange.answer.rfind("ERR 3", 0) == 0)) return exchange;
    std::this_thread::sleep_for(kBusyRetryEvery);
  }
}

int run_script(SerialPort& port, const std::vector<std::string>& commands, const Arguments& a) {
  std::unique_ptr<RecordCsv> csv;
  if (!a.out.empty()) csv = std::make_unique<RecordCsv>(a.out);
  std::string failed;
  std::size_t sent = 0;
  for (const std::string& command : commands) {
    const Exchange e = send_and_wait(port, command, a.timeout_s, !a.no_retry, [&](const std::string& line) {
      if (csv && csv->take(line)) return;
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    });
    ++sent;
    if (!a.quiet) std::fprintf(stderr, "%s -> %s\n", command.c_str(), e.answer.c_str());
    if (e.answer != "OK") {
      failed = "'" + command + "' answered " + e.answer;
      break;
    }
  }
  std::printf("sent=%zu\n", sent);
  if (csv) std::printf("records=%zu\nout=%s\n", csv->records(), a.out.c_str());
  if (!failed.empty()) throw std::runtime_error(failed);
  if (csv && csv->records() == 0) throw std::runtime_error("no readtestdata records arrived for " + a.out);
  return 0;
}

// --------------------------------------------------------------------------------- interactive
class RawTerminal {
 public:
  RawTerminal() {
    ::tcgetattr(STDIN_FILENO, &saved_);
    termios raw = saved_;
    raw.c_lflag &= ~tcflag_t(ICANON | ECHO | ISIG | IEXTEN);
    raw.c_iflag &= ~tcflag_t(IXON | ICRNL);
    raw.c_cc[VMIN] = 1;
    raw.c_cc[VTIME] = 0;
    ::tcsetattr(STDIN_FILENO, TCSANOW, &raw);
  }
  ~RawTerminal() { ::tcsetattr(STDIN_FILENO, TCSANOW, &saved_); }
  RawTerminal(const RawTerminal&) = delete;
  RawTerminal& operator=(const RawTerminal&) = delete;

 private:
  termios saved_{};
};

void redraw(const LineEditor& editor) {
  std::string s = "\r\033[K> " + editor.text();
  const std::size_t back = editor.text().size() - editor.cursor();
  if (back > 0) s += "\033[" + std::to_string(back) + "D";
  std::fwrite(s.data(), 1, s.size(), stdout);
  std::fflush(stdout);
}

int run_interactive(SerialPort& port, const Arguments& a) {
  std::unique_ptr<RecordCsv> csv;
  if (!a.out.empty()) csv = std::make_unique<RecordCsv>(a.out);
  std::fprintf(stderr, "connected to %s at %u 8N1; arrows edit and recall, Ctrl-C or Ctrl-D quits\n", a.device.c_str(),
               a.baud);
  RawTerminal raw;
  LineEditor editor;
  LineSplitter lines;
  redraw(editor);
  for (;;) {
    pollfd fds[2] = {{STDIN_FILENO, POLLIN, 0}, {port.fd(), POLLIN, 0}};
    if (::poll(fds, 2, 200) < 0) continue;
    if (fds[1].revents) {
      char buffer[4096];
      const std::size_t n = port.read(buffer, sizeof buffer, 0);
      std::fputs("\r\033[K", stdout);
      lines.feed(buffer, n, [&](const std::string& line) {
        if (csv) csv->take(line);
        std::printf("%s\r\n", line.c_str());
      });
      if (!lines.partial().empty()) std::printf("%s\r\n", lines.take_partial().c_str());
      redraw(editor);
    }
    if (fds[0].revents) {
      char byte;
      if (::read(STDIN_FILENO, &byte, 1) != 1) break;
      const LineEditor::Event event = editor.feed(byte);
      if (event == LineEditor::Event::end_of_input) break;
      if (event == LineEditor::Event::line) {
        const std::string line = editor.take_line();
        std::printf("\r\033[K> %s\r\n", line.c_str());
        port.write(line + "\n");
      }
      redraw(editor);
    }
  }
  std::fputs("\r\n", stdout);
  if (csv) std::printf("records=%zu\nout=%s\n", csv->records(), a.out.c_str());
  return 0;
}

}  // namespace

int run_term_command(int argc, char** argv) {
  Arguments a;
  CLI::App app{"dynweigh term: a console client for a serial device or pty (raw, 8N1).\n"
               "Interactive on a terminal: line editing (arrows, Home/End, Ctrl-A/E/U) and a history (up/down).\n"
               "With --send (repeatable) or with lines on stdin: each line is sent once the previous one was\n"
               "answered OK or ERR; `ERR 3 busy` is retried every 0.1 s until --timeout. --out captures the\n"
               "readtestdata records into a CSV (header jiffy,raw,filtered,marker). Exit 1 if a line is answered\n"
               "ERR or not answered in time."};
  app.add_option("device", a.device, "serial device or pty, e.g. /dev/ttyUSB0 or the console= of dynweigh-fw --console pty")
      ->required();
  app.add_option("--baud", a.baud, "line speed, 8N1")->capture_default_str();
  app.add_option("--send", a.send, "a console line to send (repeatable; in order)");
  app.add_option("--out", a.out, "write the readtestdata records received to this CSV");
  app.add_option("--timeout", a.timeout_s, "seconds to wait for each line's OK or ERR")->capture_default_str()->check(
      CLI::Range(0.1, 86400.0));
  app.add_flag("--no-retry", a.no_retry, "do not resend a line answered ERR 3 busy");
  app.add_flag("-q,--quiet", a.quiet, "do not echo each line's answer on stderr");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh term")) return *exit_status;
  try {
    SerialPort port(a.device, a.baud);
    port.discard_input();
    if (!a.send.empty()) return run_script(port, a.send, a);
    if (::isatty(STDIN_FILENO)) return run_interactive(port, a);
    std::vector<std::string> commands;
    for (std::string line; std::getline(std::cin, line);) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty()) commands.push_back(line);
    }
    return run_script(port, commands, a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynweigh term: %s\n", e.what());
    return 1;
  }
}

}  // namespace dynweigh::tools
