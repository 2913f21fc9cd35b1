#include "core/util/files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include <fmt/format.h>

namespace hyfal {

namespace fs = std::filesystem;

void write_file_atomic(const fs::path& path, const std::string& text, std::string_view what) {
  const fs::path tmp = path.string() + ".tmp";
  const auto fail = [&](const std::string& step, int error) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw EnvironmentError(fmt::format("cannot write {}{}'{}': {}: {}", what, what.empty() ? "" : " ", path.string(),
                                       step, std::strerror(error)));
  };
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  if (ec) fail(fmt::format("cannot create '{}'", path.parent_path().string()), ec.value());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot create it", errno);
  for (std::size_t written = 0; written < text.size();) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;
      ::close(fd);
      fail("write failed", error);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) fail("write failed", errno);  // e.g. ENOSPC reported at close (NFS)
  fs::rename(tmp, path, ec);
  if (ec) fail("cannot rename the temporary file", ec.value());
}

}  // namespace hyfal
