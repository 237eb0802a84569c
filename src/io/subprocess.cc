#include "io/subprocess.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

extern char** environ;

namespace softwrist::io {
namespace {

// posix_spawn's file actions, freed on every path.
class FileActions {
 public:
  explicit FileActions(const ProcessOptions& options) {
    posix_spawn_file_actions_init(&actions_);
    redirect(STDOUT_FILENO, options.stdout_file);
    redirect(STDERR_FILENO, options.stderr_file);
  }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions_); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
  void input_from(int fd) { posix_spawn_file_actions_adddup2(&actions_, fd, STDIN_FILENO); }
  const posix_spawn_file_actions_t* get() const { return &actions_; }

 private:
  void redirect(int fd, const std::filesystem::path& file) {
    if (file.empty()) return;
    paths_.push_back(file.string());  // the path must outlive the spawn
    posix_spawn_file_actions_addopen(&actions_, fd, paths_.back().c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  }
  posix_spawn_file_actions_t actions_;
  std::vector<std::string> paths_;
};

pid_t spawn(const std::vector<std::string>& argv, const FileActions& actions) {
  if (argv.empty()) throw std::runtime_error("run_process: no program given");
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int error = posix_spawnp(&pid, args[0], actions.get(), nullptr, args.data(), environ);
  if (error != 0) throw std::runtime_error(fmt::format("cannot run {}: {}", argv[0], std::strerror(error)));
  return pid;
}

int wait_for(pid_t pid, const std::string& program) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error(fmt::format("waiting for {}: {}", program, std::strerror(errno)));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

int run_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
  const FileActions actions(options);
  return wait_for(spawn(argv, actions), argv.front());
}

ProcessInput::ProcessInput(const std::vector<std::string>& argv, const ProcessOptions& options)
    : program_(argv.empty() ? "" : argv.front()) {
  // A socket pair rather than a pipe: send() with MSG_NOSIGNAL reports a child that stopped reading as an error
  // instead of raising SIGPIPE in the whole process.
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    throw std::runtime_error(fmt::format("cannot run {}: socketpair: {}", program_, std::strerror(errno)));
  }
  FileActions actions(options);
  actions.input_from(fds[0]);  // dup2 clears close-on-exec on the child's stdin only
  try {
    pid_ = spawn(argv, actions);
  } catch (...) {
    close(fds[0]);
    close(fds[1]);
    throw;
  }
  close(fds[0]);
  shutdown(fds[1], SHUT_RD);
  input_ = fds[1];
}

ProcessInput::~ProcessInput() {
  if (pid_ > 0) {
    try {
      finish();
    } catch (...) {  // a destructor must not throw; finish() was the place to see the error
    }
  }
}

void ProcessInput::write(const unsigned char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t sent = send(input_, data, size, MSG_NOSIGNAL);
    if (sent < 0 && errno == EINTR) continue;
    if (sent <= 0)
      throw std::runtime_error(fmt::format("{} stopped reading its input: {}", program_, std::strerror(errno)));
    data += sent;
    size -= static_cast<std::size_t>(sent);
  }
}

int ProcessInput::finish() {
  if (input_ >= 0) close(input_);
  input_ = -1;
  const pid_t pid = pid_;
  pid_ = -1;
  return pid > 0 ? wait_for(pid, program_) : -1;
}

}  // namespace softwrist::io
