#pragma once

// Interrupts (docs/campaign.md, "Interrupts"): inside an InterruptScope, SIGINT and SIGTERM do not
// end the process; they set a flag that long loops (the sweep) poll, so the cell in flight
// finishes, what is done is committed, and the command says how to resume. A second signal ends
// the process at once, the usual way.

#include <stdexcept>
#include <string>

namespace emrm::core {

/// While alive, SIGINT and SIGTERM set the interrupt flag instead of ending the process; the
/// previous handlers come back when it ends. A signal that was ignored when the scope began (a
/// background job of a non-interactive shell ignores SIGINT) stays ignored. Not nestable.
class InterruptScope {
 public:
  InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  ~InterruptScope();
};

/// The signal received inside an InterruptScope (SIGINT or SIGTERM), or 0.
[[nodiscard]] int interrupt_signal() noexcept;

/// Sets the flag as a signal inside an InterruptScope does, for a host that receives the signals
/// itself: the Python module keeps the interpreter's own SIGINT handler and, when it reports
/// Ctrl-C, stops a sweep this way (docs/python.md). clear_interrupt() lowers the flag again, as an
/// InterruptScope does when it begins.
void request_interrupt(int signal) noexcept;
void clear_interrupt() noexcept;

/// Thrown by a long operation that stopped at an interrupt after keeping its work; the command
/// line prints the message and exits 128 + signal (130 for SIGINT, 143 for SIGTERM).
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, const std::string& message) : std::runtime_error(message), signal_(signal) {}
  [[nodiscard]] int signal() const noexcept { return signal_; }

 private:
  int signal_;
};

}  // namespace emrm::core
