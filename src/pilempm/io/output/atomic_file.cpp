#include "pilempm/io/output/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "pilempm/core/error.hpp"
#include "pilempm/io/output/output_folder.hpp"

namespace pilempm {

namespace fs = std::filesystem;

namespace {

std::string system_error_text() {
  return std::strerror(errno);
}

// Writes all of `content` to a new file and syncs it; false with errno set on failure.
bool write_and_sync(const fs::path& path, std::string_view content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int saved = errno;
      ::close(fd);
      errno = saved;
      return false;
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int saved = errno;
    ::close(fd);
    errno = saved;
    return false;
  }
  return ::close(fd) == 0;
}

}  // namespace

fs::path temporary_path_for(const fs::path& path) {
  note_output_file(path);  // listed in its run folder's list of files (output_folder.hpp)
  static std::atomic<unsigned long> count{0};
  fs::path tmp = path;
  tmp += fmt::format(".{}-{}.tmp", ::getpid(), count++);
  return tmp;
}

void write_file_atomically(const fs::path& path, std::string_view content) {
  const fs::path tmp = temporary_path_for(path);
  if (!write_and_sync(tmp, content)) {
    const std::string why = system_error_text();
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(fmt::format("cannot write {}: {}", tmp.string(), why));
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(
        fmt::format("cannot rename {} to {}: {}", tmp.string(), path.string(), ec.message()));
  }
}

void prepare_output_directory(const fs::path& directory) {
  const fs::path dir = directory.empty() ? fs::path(".") : directory;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw Error(
        fmt::format("output folder {}: cannot create it{}", dir.string(),
                    ec ? ": " + ec.message() : std::string(" (a file of that name exists)")));
  const fs::path probe = dir / fmt::format(".pilempm-write-check-{}", ::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0)
    throw Error(
        fmt::format("output folder {} is not writable: {}", dir.string(), system_error_text()));
  ::close(fd);
  fs::remove(probe, ec);
}

void check_output_file(const fs::path& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec))
    throw Error(fmt::format("output file {} is a folder", file.string()));
  prepare_output_directory(file.parent_path());
}

}  // namespace pilempm
