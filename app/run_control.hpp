#pragma once
/// \file
/// Stopping a run cleanly on SIGINT (Ctrl-C) or SIGTERM: the handlers only set an atomic
/// flag; the step loops poll stop_signal() and wind down, writing what they have with
/// status "interrupted" and exiting with 128 + the signal (130, 143). A second signal of
/// the same kind is not caught (the handler is reset after the first): it ends the process
/// at once, as the default action does.

namespace cleave::app {

/// Installs the SIGINT and SIGTERM handlers (once per run command).
void install_stop_handlers();

/// The signal that asked the run to stop (SIGINT or SIGTERM), or 0.
int stop_signal();

/// The exit code of a run stopped by `signal`: 128 + signal.
inline int exit_code_for_signal(int signal) { return 128 + signal; }

/// "SIGINT", "SIGTERM" or "signal N".
const char* signal_name(int signal);

}  // namespace cleave::app
