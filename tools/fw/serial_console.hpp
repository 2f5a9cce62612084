#pragma once
// The console on a serial line, for every plant dynweigh-fw drives: a pty it makes (with its
// optional --pty-link) or an existing device. It announces console=<device> on stdout, then
// hands the console to the plant's loop.
#include <cstdio>
#include <optional>
#include <string>

#include "dynweigh/hal/host/pty_console.hpp"
#include "dynweigh/hal/host/tty_console.hpp"
#include "pty_link.hpp"

namespace dynweigh::tools {

// `serve(console)` on the serial console --console names; nothing for `stdio`.
template <typename Serve>
std::optional<int> serve_on_serial_console(const std::string& console_option, const std::string& pty_link,
                                           Serve&& serve) {
  if (console_option == "stdio") return std::nullopt;
  const auto announce = [](const std::string& device) {
    std::printf("console=%s\n", device.c_str());
    std::fflush(stdout);
  };
  if (console_option == "pty") {
    hal::host::PtyConsole console;
    const PtyLink link(pty_link, console.device_path());
    announce(console.device_path());
    return serve(console);
  }
  hal::host::TtyConsole console(console_option);
  announce(console.device_path());
  return serve(console);
}

}  // namespace dynweigh::tools
