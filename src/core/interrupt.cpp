#include "emrm/core/interrupt.hpp"

#include <atomic>
#include <csignal>

namespace emrm::core {
namespace {

std::atomic<int> g_signal{0};
struct sigaction g_previous_int {};
struct sigaction g_previous_term {};

extern "C" void on_interrupt(int signal) {
  if (g_signal.exchange(signal) != 0) {  // the second one: end now, the usual way
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
}

void install(int signal, struct sigaction& previous) {
  sigaction(signal, nullptr, &previous);
  if (previous.sa_handler == SIG_IGN) return;  // ignored by whoever started us: keep it so
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(signal, &action, nullptr);
}

}  // namespace

InterruptScope::InterruptScope() {
  g_signal = 0;
  install(SIGINT, g_previous_int);
  install(SIGTERM, g_previous_term);
}

InterruptScope::~InterruptScope() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

int interrupt_signal() noexcept { return g_signal.load(); }

void request_interrupt(int signal) noexcept { g_signal = signal; }

void clear_interrupt() noexcept { g_signal = 0; }

}  // namespace emrm::core
