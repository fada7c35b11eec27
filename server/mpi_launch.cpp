#include "server/mpi_launch.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/simulation/event_stream.hpp"

namespace kessler::server {
namespace {

namespace fs = std::filesystem;

// A cancelled job that has not ended this long after its stop lines is killed (its process group).
constexpr auto kCancelGrace = std::chrono::seconds(30);

fs::path make_private_dir(const std::string& work_dir) {
  const fs::path base = work_dir.empty() ? fs::temp_directory_path() : fs::path(work_dir);
  std::string pattern = (base / "kesslerd-mpi-XXXXXX").string();
  if (!::mkdtemp(pattern.data()))
    throw std::runtime_error("cannot make a directory in " + base.string() + ": " + std::strerror(errno));
  return pattern;
}

void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
}

std::string tail_of(const fs::path& path, std::size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  std::string text = all.str();
  if (text.size() > max_bytes) text.replace(0, text.size() - max_bytes, "...");
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

std::string describe_status(int status) {
  if (WIFEXITED(status)) return "exit status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return "killed by signal " + std::to_string(WTERMSIG(status));
  return "status " + std::to_string(status);
}

// The launched job: its process (the leader of its own group) and the pipe ends the daemon keeps.
struct Job {
  pid_t pid = -1;
  int stdin_fd = -1;   // stop lines
  int stdout_fd = -1;  // records
  std::optional<int> status;

  int wait() {
    if (!status) {
      int s = 0;
      while (::waitpid(pid, &s, 0) < 0 && errno == EINTR) {
      }
      status = s;
    }
    return *status;
  }
};

// Forks and execs argv with stdin and stdout on pipes and stderr into `stderr_path`. In the child only
// async-signal-safe calls: the daemon has many threads.
Job start_job(const std::vector<std::string>& words, const fs::path& stderr_path) {
  std::vector<char*> argv;
  argv.reserve(words.size() + 1);
  for (const std::string& w : words) argv.push_back(const_cast<char*>(w.c_str()));
  argv.push_back(nullptr);
  int in[2], out[2];
  if (::pipe2(in, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  if (::pipe2(out, O_CLOEXEC) != 0) {
    ::close(in[0]);
    ::close(in[1]);
    throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  }
  const int err = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  const pid_t pid = err < 0 ? -1 : ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);  // the daemon blocks SIGTERM for its sigwait
    ::signal(SIGPIPE, SIG_DFL);
    ::dup2(in[0], 0);
    ::dup2(out[1], 1);
    ::dup2(err, 2);
    ::execvp(argv[0], argv.data());
    const char message[] = "kesslerd: cannot start the MPI launcher\n";
    [[maybe_unused]] ssize_t n = ::write(2, message, sizeof message - 1);
    ::_exit(127);
  }
  const int fork_errno = errno;
  ::close(in[0]);
  ::close(out[1]);
  if (err >= 0) ::close(err);
  if (pid < 0) {
    ::close(in[1]);
    ::close(out[0]);
    throw std::runtime_error(std::string("cannot start the MPI launcher: ") + std::strerror(fork_errno));
  }
  ::setpgid(pid, pid);  // also here, so that a signal sent at once finds the group
  return Job{pid, in[1], out[0], std::nullopt};
}

// Turns the run's controls into stop lines on the job's stdin until `done`; kills the job's process
// group when a cancel is not obeyed in time.
class StopForwarder {
 public:
  StopForwarder(Job& job, RunControl& control) : job_(job), control_(control) {
    thread_ = std::thread([this] { loop(); });
  }
  ~StopForwarder() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

 private:
  void loop() {
    // A job that has ended closes the pipe: its write fails with EPIPE rather than signal the daemon.
    sigset_t pipe_signal;
    sigemptyset(&pipe_signal);
    sigaddset(&pipe_signal, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_signal, nullptr);
    int lines_sent = 0;
    std::optional<std::chrono::steady_clock::time_point> cancelled_at;
    bool killed = false;
    std::unique_lock lock(mutex_);
    while (!cv_.wait_for(lock, std::chrono::milliseconds(100), [this] { return done_; })) {
      const int wanted = control_.cancel ? 2 : control_.stop_after_checkpoint ? 1 : 0;
      for (; lines_sent < wanted; ++lines_sent)
        if (::write(job_.stdin_fd, "\n", 1) != 1) break;
      if (control_.cancel && !cancelled_at) cancelled_at = std::chrono::steady_clock::now();
      if (cancelled_at && !killed && std::chrono::steady_clock::now() - *cancelled_at > kCancelGrace) {
        ::kill(-job_.pid, SIGKILL);
        killed = true;
      }
    }
  }
  Job& job_;
  RunControl& control_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool done_ = false;
  std::thread thread_;
};

std::vector<std::string> command_of(const MpiLaunch& launch, const RanksRun& run, const fs::path& dir) {
  std::vector<std::string> words = launch.launcher;
  words.push_back(launch.program);
  words.push_back((dir / "scenario.pb").string());
  words.push_back("--event-stream");
  if (run.threads > 0) words.insert(words.end(), {"--threads", std::to_string(run.threads)});
  if (run.checkpoint) words.insert(words.end(), {"--resume", (dir / "resume.ckpt").string()});
  if (!run.datasets_dir.empty()) words.insert(words.end(), {"--datasets", run.datasets_dir});
  if (!run.traffic_dir.empty()) words.insert(words.end(), {"--traffic-plans", run.traffic_dir});
  return words;
}

RunSummary run_job(Job& job, EventSink& sink, RunControl& control, const fs::path& stderr_path) {
  std::optional<StopForwarder> forwarder(std::in_place, job, control);
  auto ended_early = [&] {
    ::close(job.stdout_fd);
    job.stdout_fd = -1;
    const int status = job.wait();
    std::string why = "the MPI job ended without the run's end (" + describe_status(status) + ")";
    const std::string err = tail_of(stderr_path, 2000);
    return err.empty() ? why : why + ": " + err;
  };
  bool lost = false;
  auto lost_job = [&] {
    lost = true;
    return ended_early();
  };
  try {
    RunSummary summary = replay_event_stream(job.stdout_fd, sink, lost_job);
    forwarder.reset();
    ::close(job.stdin_fd);  // the ranks' stop-line readers end
    job.stdin_fd = -1;
    job.wait();
    return summary;
  } catch (const std::exception& e) {
    if (!job.status) ::kill(-job.pid, SIGKILL);  // a stream that broke off: the job is of no more use
    job.wait();
    // kessler-mpi's exit 2 is a refusal (bad input, too many ranks): the same again would be refused.
    const bool refused = job.status && WIFEXITED(*job.status) && WEXITSTATUS(*job.status) == 2;
    if (lost && !refused) throw MpiJobLost(e.what());
    throw;
  }
}

}  // namespace

std::optional<std::vector<std::string>> split_launcher(const std::string& line, std::string& error) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  char quote = 0;
  for (char c : line) {
    if (quote) {
      if (c == quote)
        quote = 0;
      else
        word += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_word = true;
    } else if (c == ' ' || c == '\t') {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
    } else {
      word += c;
      in_word = true;
    }
  }
  if (quote) {
    error = std::string("an unclosed ") + quote;
    return std::nullopt;
  }
  if (in_word) words.push_back(word);
  if (words.empty()) {
    error = "no launcher command";
    return std::nullopt;
  }
  return words;
}

std::string default_mpi_program() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("kessler-mpi") : (self.parent_path() / "kessler-mpi").string();
}

RunSummary run_on_ranks(const MpiLaunch& launch, const RanksRun& run, EventSink& sink, RunControl& control) {
  fs::path dir;
  try {
    dir = make_private_dir(launch.work_dir);
    write_file(dir / "scenario.pb", run.scenario->SerializeAsString());
    if (run.checkpoint) write_file(dir / "resume.ckpt", *run.checkpoint);
  } catch (const std::exception& e) {
    sink.on_failed(e.what());
    throw;
  }
  struct RemoveDir {
    fs::path dir;
    ~RemoveDir() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } remove_dir{dir};
  const fs::path stderr_path = dir / "stderr.log";
  Job job;
  try {
    const std::vector<std::string> words = command_of(launch, run, dir);
    std::string line;
    for (const std::string& w : words) line += (line.empty() ? "" : " ") + w;
    std::cerr << "kesslerd: run " << run.run_id
              << (run.checkpoint ? " from the checkpoint at step " + std::to_string(run.checkpoint_step)
                                 : std::string())
              << ": MPI job: " << line << std::endl;
    job = start_job(words, stderr_path);
  } catch (const std::exception& e) {
    sink.on_failed(e.what());
    throw;
  }
  struct CloseFds {
    Job& job;
    ~CloseFds() {
      if (job.stdin_fd >= 0) ::close(job.stdin_fd);
      if (job.stdout_fd >= 0) ::close(job.stdout_fd);
    }
  } close_fds{job};
  return run_job(job, sink, control, stderr_path);
}

}  // namespace kessler::server
