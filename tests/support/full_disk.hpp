#pragma once
// Fault injection for writers: a tiny tmpfs that fills up (needs root or CAP_SYS_ADMIN), and a
// forked child whose files may not grow past a limit (RLIMIT_FSIZE, works unprivileged). Both make
// write(2) fail part-way, as a full disk does: ENOSPC on the tmpfs, EFBIG under the limit.
#include <fcntl.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace dmgplace::test {

// A tmpfs of `size` bytes (mount's syntax: "64k") on a fresh folder, unmounted when destroyed.
class SmallDisk {
 public:
  explicit SmallDisk(const std::string& size = "64k") {
    if (::mount("tmpfs", dir_.path().c_str(), "tmpfs", MS_NOSUID | MS_NODEV, ("size=" + size).c_str()) == 0)
      mounted_ = true;
    else why_ = std::string("cannot mount a tmpfs (") + std::strerror(errno) + "; needs root)";
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(dir_.path().c_str(), MNT_DETACH);  // before dir_ removes the folder
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;

  bool mounted() const { return mounted_; }
  const std::string& why_not() const { return why_; }
  const std::filesystem::path& path() const { return dir_.path(); }
  std::filesystem::path operator/(const std::string& name) const { return dir_.path() / name; }

  // Fills the disk to the last byte with `name`, so the next write of any size fails.
  void fill(const std::string& name = "filler") const {
    const int fd = ::open((dir_.path() / name).c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) return;
    const std::vector<char> block(4096, 'x');
    while (::write(fd, block.data(), block.size()) > 0) {
    }
    while (::write(fd, block.data(), 1) > 0) {
    }
    ::close(fd);
  }

  // Every name in the folder but `except`: what a failed writer left behind.
  std::vector<std::string> files_except(const std::string& except = "filler") const {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir_.path()))
      if (!e.is_directory() && e.path().filename() != except) names.push_back(e.path().filename().string());
    return names;
  }

 private:
  TempDir dir_;
  bool mounted_ = false;
  std::string why_;
};

// Limits the calling process's file size to `bytes` and makes an oversized write fail with EFBIG
// instead of killing the process with SIGXFSZ. Only for a forked child: it is inherited by exec.
inline void limit_file_size(rlim_t bytes) {
  ::signal(SIGXFSZ, SIG_IGN);
  const rlimit lim{bytes, bytes};
  ::setrlimit(RLIMIT_FSIZE, &lim);
}

struct ChildRun {
  int code = -1;        // exit code, -1 when killed by a signal
  std::string message;  // the dmgplace::Error's text, or the command's output
};

// What a forked child wrote into the pipe `fds` (the parent closes the write end), and how it exited.
inline ChildRun collect_child(pid_t pid, int fds[2]) {
  ::close(fds[1]);
  ChildRun r;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) r.message.append(buf, std::size_t(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Runs f() in a forked child limited to `bytes` per file. Exit code 0 and the message when f
// threw a dmgplace::Error, 2 when it returned, 3 when it threw anything else.
template <class F>
ChildRun with_file_size_limit(rlim_t bytes, F&& f) {
  int fds[2];
  if (::pipe(fds) != 0) return {};
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    limit_file_size(bytes);
    int code = 2;
    std::string text = "(no dmgplace::Error)";
    try {
      f();
    } catch (const ::dmgplace::Error& e) {
      code = 0;
      text = e.what();
    } catch (...) {
      code = 3;
      text = "(another exception)";
    }
    [[maybe_unused]] auto n = ::write(fds[1], text.data(), text.size());
    ::_exit(code);
  }
  return collect_child(pid, fds);
}

// `dmgplace ARGS...` in a child limited to `bytes` per file, started with an argument vector (no
// shell); stdout and stderr together.
inline ChildRun cli_with_file_size_limit(rlim_t bytes, const std::vector<std::string>& args) {
  std::vector<std::string> argv{cli_path()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> c_argv;
  for (auto& a : argv) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);
  int fds[2];
  if (::pipe(fds) != 0) return {};
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    ::dup2(fds[1], STDOUT_FILENO);
    ::dup2(fds[1], STDERR_FILENO);
    ::close(fds[1]);
    limit_file_size(bytes);
    ::execv(c_argv[0], c_argv.data());
    ::_exit(127);
  }
  return collect_child(pid, fds);
}

}  // namespace dmgplace::test
