// SIGINT and SIGTERM as a request to stop: the handler only sets a sig_atomic_t flag; the frame
// loop checks it between steps and frames, so the step and frame being written finish and every
// index stays consistent with the files present. The handler resets itself: a second signal
// ends the process at once.
#pragma once

namespace apiclab {

// Installs the handlers (SIGINT, SIGTERM) for a headless command.
void install_stop_handlers();
// The signal that asked to stop (SIGINT or SIGTERM), or 0.
int stop_signal();
// The exit status for a stop by `signal`: 128 + signal (130 for SIGINT, 143 for SIGTERM).
inline int stop_exit_code(int signal) { return 128 + signal; }

}  // namespace apiclab
