#include "commands.hpp"

namespace emrm::cli {
void register_ca_command(CLI::App& app, int& exit_code) {
  (void)app;
  (void)exit_code;
}
}  // namespace emrm::cli
