// End-to-end harness: the real kesslerd and kessler binaries as child processes on 127.0.0.1, with a
// free port chosen by the daemon (--listen 127.0.0.1:0 --port-file).
#pragma once

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "tests/service/temp_dir.hpp"

namespace kessler::test {

inline std::string bin(const std::string& name) {
  return std::string(KESSLER_BIN_DIR) + "/" + name;
}
inline std::string source_path(const std::string& rel) {
  return std::string(KESSLER_SOURCE_DIR) + "/" + rel;
}
// A scenario of a few objects for a few minutes: the suites' quickest complete run.
inline const std::string kTinyScenario = source_path("tests/service/scenarios/tiny.yaml");

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// One kesslerd process over a database that outlives it.
class Daemon {
 public:
  Daemon(std::string db_path, std::vector<std::string> extra = {})
      : db_path_(std::move(db_path)), extra_(std::move(extra)) {}
  ~Daemon() {
    if (pid_ > 0) kill9();
  }

  void start() {
    std::string port_file = db_path_ + ".port";
    std::remove(port_file.c_str());
    log_ = db_path_ + ".log";
    pid_ = fork();
    if (pid_ == 0) {
      prctl(PR_SET_PDEATHSIG, SIGKILL);  // a test killed midway leaves no daemon behind
      std::freopen(log_.c_str(), "a", stdout);
      std::freopen(log_.c_str(), "a", stderr);
      std::vector<std::string> args = {bin("kesslerd"), "--listen",    "127.0.0.1:0", "--db",
                                       db_path_,        "--port-file", port_file};
      args.insert(args.end(), extra_.begin(), extra_.end());
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
      std::string text = read_text(port_file);
      if (!text.empty()) {
        port_ = std::stoi(text);
        return;
      }
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        throw std::runtime_error("kesslerd exited at start: " + read_text(log_));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    throw std::runtime_error("kesslerd did not start: " + read_text(log_));
  }

  // SIGTERM, then the exit status (or -1 after a 60 s timeout, then SIGKILL).
  int terminate() {
    ::kill(pid_, SIGTERM);
    auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    kill9();
    return -1;
  }

  void kill9() {
    ::kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
  }

  bool alive() const { return pid_ > 0 && waitpid(pid_, nullptr, WNOHANG) == 0; }
  pid_t pid() const { return pid_; }
  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  std::string log() const { return read_text(log_); }

 private:
  std::string db_path_;
  std::vector<std::string> extra_;
  std::string log_;
  pid_t pid_ = -1;
  int port_ = 0;
};

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
  // The last non-empty line of stdout.
  std::string last_line() const {
    std::istringstream s(out);
    std::string line, last;
    while (std::getline(s, line))
      if (!line.empty()) last = line;
    return last;
  }
};

// Runs `kessler ARGS` (a shell-quoted argument string) with stdout and stderr captured.
inline CliResult cli(const TempDir& dir, const std::string& args, const std::string& env = "") {
  static int counter = 0;
  std::string out = dir.path() + "/cli" + std::to_string(++counter) + ".out";
  std::string err = dir.path() + "/cli" + std::to_string(counter) + ".err";
  std::string cmd = env + " " + bin("kessler") + " " + args + " > " + out + " 2> " + err;
  int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

}  // namespace kessler::test
