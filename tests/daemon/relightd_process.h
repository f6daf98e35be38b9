// The relightd executable as a child process for tests: started with
// posix_spawn, its stderr and stdout in a log file the test waits on.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <chrono>
#include <iterator>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "daemon_test_support.h"

extern char** environ;

namespace relight::daemon::testing {

class Relightd {
 public:
  // Starts relightd with `args`, stderr and stdout to a log file.
  explicit Relightd(std::vector<std::string> args, const std::string& log_name)
      : log_(::testing::TempDir() + "/" + log_name) {
    args.insert(args.begin(), RELIGHTD_PATH);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    EXPECT_EQ(posix_spawn(&pid_, RELIGHTD_PATH, &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Relightd() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      Wait();
    }
  }
  // Waits (up to 60 s) until the log matches `pattern`; returns the first group.
  std::string WaitForLog(const std::string& pattern) {
    const std::regex re(pattern);
    for (int i = 0; i < 6000; ++i) {
      std::smatch m;
      const std::string text = ReadAll(log_);
      if (std::regex_search(text, m, re)) return m.size() > 1 ? m[1].str() : m[0].str();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "no '" << pattern << "' in the log:\n" << ReadAll(log_);
    return "";
  }
  // Waits (up to 60 s) until `pattern` occurs `n` times in the log.
  bool WaitForLogCount(const std::string& pattern, int n) {
    const std::regex re(pattern);
    for (int i = 0; i < 6000; ++i) {
      const std::string text = ReadAll(log_);
      const auto count = std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator());
      if (count >= n) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "'" << pattern << "' not " << n << " times in the log:\n" << ReadAll(log_);
    return false;
  }
  // Still running (not exited, not killed).
  bool Running() {
    int status = 0;
    if (pid_ <= 0) return false;
    if (waitpid(pid_, &status, WNOHANG) == 0) return true;
    pid_ = -1;  // reaped
    return false;
  }
  void Signal(int sig) { kill(pid_, sig); }
  int Wait() {
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  std::string log() const { return ReadAll(log_); }

 private:
  std::string log_;
  pid_t pid_ = -1;
};

}  // namespace relight::daemon::testing
