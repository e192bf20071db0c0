#include "sdvi/file_util.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace sdvi {
namespace {

std::string ErrnoText() { return std::strerror(errno); }

// A unique sibling of path with the same extension: "dir/.name.sdvi-tmp-PID-N.ext".
std::string TempSibling(const std::string& path) {
  static std::atomic<int> counter{0};
  std::filesystem::path p(path);
  std::string name(".");
  name.append(p.stem().string())
      .append(".sdvi-tmp-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(counter++))
      .append(p.extension().string());
  return (p.parent_path() / name).string();
}

}  // namespace

StatusOr<std::vector<uint8_t>> ReadFileBytes(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return Status(StatusCode::kNotFound, path + ": no such file");
  if (std::filesystem::is_directory(path, ec))
    return Status(StatusCode::kIoError, path + ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open for reading: " + ErrnoText());
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  if (size < 0) return Status(StatusCode::kIoError, path + ": cannot determine size");
  in.seekg(0, std::ios::beg);
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    return Status(StatusCode::kIoError, path + ": read failed");
  return bytes;
}

Status WriteFileAtomic(const std::string& path, const void* data, size_t size) {
  return WriteViaTempFile(path, [&](const std::string& tmp) -> Status {
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return Status(StatusCode::kIoError, path + ": cannot create: " + ErrnoText());
    const auto* p = static_cast<const uint8_t*>(data);
    size_t left = size;
    while (left > 0) {
      ssize_t n = ::write(fd, p, left);
      if (n < 0) {
        if (errno == EINTR) continue;
        std::string why = ErrnoText();
        ::close(fd);
        return Status(StatusCode::kIoError, path + ": write failed: " + why);
      }
      p += n;
      left -= static_cast<size_t>(n);
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0)
      return Status(StatusCode::kIoError, path + ": flush failed: " + ErrnoText());
    return Status::Ok();
  });
}

Status WriteViaTempFile(const std::string& path,
                        const std::function<Status(const std::string& temp_path)>& write) {
  if (path.empty()) return Status(StatusCode::kInvalidArgument, "empty output path");
  const std::string tmp = TempSibling(path);
  Status status;
  try {
    status = write(tmp);
  } catch (const std::exception& e) {
    status = Status(StatusCode::kIoError, path + ": " + e.what());
  }
  std::error_code ec;
  if (status.ok() && !std::filesystem::exists(tmp, ec))
    status = Status(StatusCode::kIoError, path + ": the writer produced no file");
  if (!status.ok()) {
    std::filesystem::remove(tmp, ec);
    return status;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::string why = ErrnoText();
    std::filesystem::remove(tmp, ec);
    return Status(StatusCode::kIoError, path + ": rename failed: " + why);
  }
  return Status::Ok();
}

std::string FileExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace sdvi
