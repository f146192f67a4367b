#pragma once

// Starting a program without a shell, for the tests that signal it while it runs (a shell's
// background job would ignore SIGINT), and collecting what it printed once it ends.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>
#include <string>
#include <vector>

#include "run_emrm.hpp"

extern char** environ;

namespace emrm::e2e {

/// Starts `words[0]` with arguments `words` (no shell), its standard output and error into
/// DIR/stdout.txt and DIR/stderr.txt; returns its process id.
inline pid_t spawn_process(std::vector<std::string> words, const std::filesystem::path& dir) {
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, (dir / "stdout.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&files, 2, (dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  EXPECT_EQ(posix_spawn(&pid, argv[0], &files, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&files);
  return pid;
}

/// Waits for a process of spawn_process and returns its exit code (128 + signal when a signal
/// ended it) and what it printed.
inline RunResult wait_for_process(pid_t pid, const std::filesystem::path& dir) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = read_text(dir / "stdout.txt");
  r.err = read_text(dir / "stderr.txt");
  return r;
}

}  // namespace emrm::e2e
