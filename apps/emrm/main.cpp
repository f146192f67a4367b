// The emrm program: the command line of apps/emrm/cli.cpp.

#include "cli.hpp"

int main(int argc, char** argv) { return emrm::cli::run_cli(argc, argv); }
