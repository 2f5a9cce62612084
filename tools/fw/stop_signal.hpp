#pragma once
// SIGINT and SIGTERM end dynweigh-fw in an orderly way (heartbeat "stopped" to a CAN plant, the pty
// link removed): the handler sets a flag and, installed without SA_RESTART, breaks any poll(2) the
// loop is in, so it sees the flag within one jiffy.
namespace dynweigh::tools {

void install_stop_handlers();
bool stop_requested();
// The signal that asked to stop (for the exit status 128 + signal), or 0.
int stop_signal();

}  // namespace dynweigh::tools
