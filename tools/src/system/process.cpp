#include "dmgplace/tools/system/process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <utility>

#include "dmgplace/formats/error.hpp"

extern char** environ;  // POSIX: declared by no header

namespace dmgplace::tools {
namespace {

std::string errno_text(int e) { return std::strerror(e); }

// A file descriptor closed when it goes out of scope, so no path out of run_process leaks one.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : fd_(fd) {}
  Fd(Fd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  Fd& operator=(Fd&& o) noexcept {
    reset(std::exchange(o.fd_, -1));
    return *this;
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { reset(); }
  int get() const { return fd_; }
  explicit operator bool() const { return fd_ >= 0; }
  void reset(int fd = -1) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = fd;
  }

 private:
  int fd_ = -1;
};

struct Pipe {
  Fd read, write;
};

Pipe make_pipe(const std::string& program) {
  int fds[2];
  // O_CLOEXEC: a child that another thread spawns meanwhile must not hold our ends open (the
  // reader would never see end-of-file). dup2 onto 0/1/2 in our own child clears the flag.
  if (::pipe2(fds, O_CLOEXEC) != 0) throw Error(program, "", "cannot run: cannot create a pipe: " + errno_text(errno));
  return {Fd(fds[0]), Fd(fds[1])};
}

struct FileActions {
  posix_spawn_file_actions_t a;
  FileActions() { ::posix_spawn_file_actions_init(&a); }
  ~FileActions() { ::posix_spawn_file_actions_destroy(&a); }
  FileActions(const FileActions&) = delete;
  FileActions& operator=(const FileActions&) = delete;
};

// This process's environment with `extra` set on top (the last of equal names wins).
std::vector<std::string> environment_with(const std::vector<std::pair<std::string, std::string>>& extra,
                                          const std::string& program) {
  auto overridden = [&](const std::string& name, std::size_t from) {
    for (std::size_t i = from; i < extra.size(); ++i)
      if (extra[i].first == name) return true;
    return false;
  };
  std::vector<std::string> env;
  for (char** e = environ; e && *e; ++e) {
    const std::string entry = *e;
    if (!overridden(entry.substr(0, entry.find('=')), 0)) env.push_back(entry);
  }
  for (std::size_t i = 0; i < extra.size(); ++i) {
    const auto& [name, value] = extra[i];
    if (name.empty() || name.find('=') != std::string::npos)
      throw Error(program, "environment", "'" + name + "' is not a variable name");
    if (!overridden(name, i + 1)) env.push_back(name + "=" + value);
  }
  return env;
}

// The NULL-terminated char* array that posix_spawn takes, pointing into `strings`.
std::vector<char*> c_array(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

// Blocks SIGPIPE in this thread while we feed a child's stdin: a child that exits without reading
// all of it makes write() fail with EPIPE instead of killing the whole test or tool. A SIGPIPE
// raised meanwhile is consumed before the old mask comes back.
class SigpipeBlocked {
 public:
  SigpipeBlocked() {
    ::sigemptyset(&pipe_);
    ::sigaddset(&pipe_, SIGPIPE);
    sigset_t pending;
    ::sigpending(&pending);
    was_pending_ = ::sigismember(&pending, SIGPIPE) == 1;
    ::pthread_sigmask(SIG_BLOCK, &pipe_, &old_);
  }
  ~SigpipeBlocked() {
    sigset_t pending;
    ::sigpending(&pending);
    if (!was_pending_ && ::sigismember(&pending, SIGPIPE) == 1) {
      const timespec zero{};
      ::sigtimedwait(&pipe_, nullptr, &zero);
    }
    ::pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  SigpipeBlocked(const SigpipeBlocked&) = delete;
  SigpipeBlocked& operator=(const SigpipeBlocked&) = delete;

 private:
  sigset_t pipe_, old_;
  bool was_pending_ = false;
};

bool is_executable_file(const std::filesystem::path& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
}

// The child's stdin, stdout and stderr as `options` ask, through pipes made here.
void plan_child_io(FileActions& actions, const ProcessOptions& options, const std::string& program, Pipe& in, Pipe& out,
                   Pipe& err) {
  auto check = [&](int rc, const char* what) {
    if (rc != 0) throw Error(program, "", std::string("cannot run: ") + what + ": " + errno_text(rc));
  };
  if (options.input) {
    in = make_pipe(program);
    check(::posix_spawn_file_actions_adddup2(&actions.a, in.read.get(), STDIN_FILENO), "stdin");
  } else {
    // Not our stdin: a child that prompts must see end-of-file, not wait for a terminal.
    check(::posix_spawn_file_actions_addopen(&actions.a, STDIN_FILENO, "/dev/null", O_RDONLY, 0), "stdin");
  }
  out = make_pipe(program);
  check(::posix_spawn_file_actions_adddup2(&actions.a, out.write.get(), STDOUT_FILENO), "stdout");
  switch (options.stderr_to) {
    case StderrTo::inherit:
      break;
    case StderrTo::merge:
      check(::posix_spawn_file_actions_adddup2(&actions.a, out.write.get(), STDERR_FILENO), "stderr");
      break;
    case StderrTo::capture:
      err = make_pipe(program);
      check(::posix_spawn_file_actions_adddup2(&actions.a, err.write.get(), STDERR_FILENO), "stderr");
      break;
    case StderrTo::discard:
      check(::posix_spawn_file_actions_addopen(&actions.a, STDERR_FILENO, "/dev/null", O_WRONLY, 0), "stderr");
      break;
  }
  if (!options.cwd.empty())
    check(::posix_spawn_file_actions_addchdir_np(&actions.a, options.cwd.c_str()), "working folder");
}

// Feeds the child its input and reads what it writes until every pipe is closed; errno of a
// failed poll, or 0.
int exchange(const ProcessOptions& options, Pipe& in, Pipe& out, Pipe& err, ProcessResult& r) {
  std::optional<SigpipeBlocked> sigpipe;
  std::size_t written = 0;
  if (options.input) {
    sigpipe.emplace();
    // Non-blocking: a child that writes a lot before reading must not deadlock with us.
    ::fcntl(in.write.get(), F_SETFL, ::fcntl(in.write.get(), F_GETFL) | O_NONBLOCK);
    if (options.input->empty()) in.write.reset();
  }
  while (in.write || out.read || err.read) {
    pollfd fds[3];
    nfds_t n = 0;
    if (in.write) fds[n++] = {in.write.get(), POLLOUT, 0};
    if (out.read) fds[n++] = {out.read.get(), POLLIN, 0};
    if (err.read) fds[n++] = {err.read.get(), POLLIN, 0};
    if (::poll(fds, n, -1) < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    for (nfds_t i = 0; i < n; ++i) {
      if (!fds[i].revents) continue;
      if (in.write && fds[i].fd == in.write.get()) {
        const ssize_t w = ::write(in.write.get(), options.input->data() + written, options.input->size() - written);
        if (w > 0) written += std::size_t(w);
        // EPIPE: the child stopped reading; what it did is in its exit code and output.
        if ((w < 0 && errno != EAGAIN && errno != EINTR) || written == options.input->size()) in.write.reset();
        continue;
      }
      Fd& from = out.read && fds[i].fd == out.read.get() ? out.read : err.read;
      std::string& to = &from == &out.read ? r.output : r.error_output;
      char buf[65536];
      const ssize_t got = ::read(from.get(), buf, sizeof buf);
      if (got > 0) to.append(buf, std::size_t(got));
      else if (got == 0 || (errno != EINTR && errno != EAGAIN)) from.reset();
    }
  }
  return 0;
}

}  // namespace

ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
  if (argv.empty() || argv[0].empty()) throw Error("run_process", "argv", "no program to run");
  const std::string& program = argv[0];
  std::string file = program;
  // posix_spawnp resolves a relative path after the child's chdir: make it mean what it says here.
  if (file.find('/') != std::string::npos && !options.cwd.empty()) file = std::filesystem::absolute(file).string();
  std::error_code ec;
  if (!options.cwd.empty() && !std::filesystem::is_directory(options.cwd, ec))
    throw Error(program, "", "cannot run in " + options.cwd.string() + ": not a folder");

  FileActions actions;
  Pipe in, out, err;
  plan_child_io(actions, options, program, in, out, err);
  std::vector<std::string> args = argv;
  std::vector<char*> c_args = c_array(args);
  std::vector<std::string> env;
  std::vector<char*> c_env;
  if (!options.env.empty()) {
    env = environment_with(options.env, program);
    c_env = c_array(env);
  }
  pid_t pid = -1;
  // glibc reports a failed exec (and a failed file action) as posix_spawnp's return value.
  const int rc = ::posix_spawnp(&pid, file.c_str(), &actions.a, nullptr, c_args.data(),
                                options.env.empty() ? environ : c_env.data());
  if (rc != 0) {
    const bool searched = file.find('/') == std::string::npos;
    throw Error(program, "",
                "cannot run: " + errno_text(rc) + (rc == ENOENT && searched ? " (not found in $PATH)" : ""));
  }
  // Only the child uses these ends: holding them would keep our reads from ever ending.
  in.read.reset();
  out.write.reset();
  err.write.reset();

  ProcessResult r;
  const int poll_error = exchange(options, in, out, err, r);
  // Closing our ends first lets a child still writing end (EPIPE) instead of waiting forever.
  in.write.reset();
  out.read.reset();
  err.read.reset();
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw Error(program, "", "cannot wait for it: " + errno_text(errno));
  }
  if (poll_error) throw Error(program, "", "cannot read its output: " + errno_text(poll_error));
  if (WIFEXITED(status)) {
    r.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    r.signal = WTERMSIG(status);
  }
  return r;
}

std::optional<std::filesystem::path> find_executable(const std::string& name) {
  if (name.empty()) return std::nullopt;
  if (name.find('/') != std::string::npos) {
    if (is_executable_file(name)) return std::filesystem::path(name);
    return std::nullopt;
  }
  std::string search;
  if (const char* p = std::getenv("PATH")) {
    search = p;
  } else {
    // No $PATH: the system's default one, as the shell and execvp use.
    search.resize(::confstr(_CS_PATH, nullptr, 0));
    if (!search.empty()) ::confstr(_CS_PATH, search.data(), search.size());
    search.resize(std::strlen(search.c_str()));
  }
  for (std::size_t from = 0;;) {
    const std::size_t colon = search.find(':', from);
    const std::string dir = search.substr(from, colon == std::string::npos ? std::string::npos : colon - from);
    const std::filesystem::path candidate =
        std::filesystem::path(dir.empty() ? "." : dir) / name;  // "" is the working folder
    if (is_executable_file(candidate)) return candidate;
    if (colon == std::string::npos) break;
    from = colon + 1;
  }
  return std::nullopt;
}

}  // namespace dmgplace::tools
