// Starts a program as a child process and stops it when the owner goes away
// (SIGTERM, then SIGKILL after a grace period): tests stop what they start,
// and a test that crashes takes its children with it (PR_SET_PDEATHSIG).
#pragma once

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

namespace igms::test {

class ChildProcess {
 public:
  explicit ChildProcess(const std::vector<std::string>& argv) {
    pid_ = fork();
    if (pid_ == 0) {
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      std::vector<char*> args;
      for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      execv(args[0], args.data());
      _exit(127);
    }
  }
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // SIGTERM, wait up to 5 s, then SIGKILL. Returns the exit status (or -1).
  int stop() {
    if (pid_ <= 0) return exit_code_;
    kill(pid_, SIGTERM);
    exit_code_ = waitFor(std::chrono::seconds(5));
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      exit_code_ = waitFor(std::chrono::seconds(5));
    }
    return exit_code_;
  }
  // Waits for the child to exit by itself.
  int wait(std::chrono::milliseconds limit) { return waitFor(limit); }
  // Not yet reaped: started and has not exited (running() after a crash is false once checked).
  bool running() {
    waitFor(std::chrono::milliseconds(0));
    return pid_ > 0;
  }
  pid_t pid() const { return pid_; }

 private:
  int waitFor(std::chrono::milliseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    for (bool first = true; pid_ > 0 && (first || std::chrono::steady_clock::now() < end); first = false) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return exit_code_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return pid_ > 0 ? -1 : exit_code_;
  }
  pid_t pid_ = -1;
  int exit_code_ = -1;
};

}  // namespace igms::test
