#include "dmgplace/formats/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "dmgplace/formats/error.hpp"

namespace dmgplace::formats {
namespace fs = std::filesystem;

void sync_directory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // some file systems do not allow it; the rename is still atomic
  ::fsync(fd);
  ::close(fd);
}

fs::path temporary_name_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() /
         ("." + target.filename().string() + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++));
}

void remove_stale_temporaries(const fs::path& target) {
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string prefix = "." + target.filename().string() + ".tmp.";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    long pid = 0;
    try {
      pid = std::stol(name.substr(prefix.size()));
    } catch (...) {
      continue;
    }
    if (pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH) fs::remove(e.path(), ec);
  }
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
  const std::string file = path.string();
  if (path.filename().empty()) throw Error(file, "", "output path names no file");
  remove_stale_temporaries(path);
  const fs::path tmp = temporary_name_for(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(file, "", std::string("cannot create a temporary file beside it: ") + std::strerror(errno));
  const auto fail = [&](const std::string& what, int err, bool close_fd) {
    if (close_fd) ::close(fd);
    std::error_code ec;
    fs::remove(tmp, ec);  // a full disk must not be left fuller by a half-written leftover
    throw Error(file, "", what + ": " + std::strerror(err));
  };
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write failed (disk full?)", n < 0 ? errno : ENOSPC, true);
    done += std::size_t(n);
  }
  if (::fsync(fd) != 0) fail("fsync failed (disk full?)", errno, true);
  if (::close(fd) != 0) fail("close failed (disk full?)", errno, false);
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) fail("cannot rename the temporary file into place", ec.value(), false);
  sync_directory(path.parent_path());
}

}  // namespace dmgplace::formats
