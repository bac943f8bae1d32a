#include "util/atomic_file.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "util/check.h"

namespace brdfshot {
namespace fs = std::filesystem;

namespace {
std::string TempPathFor(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / (p.stem().string() + ".tmp" + std::to_string(::getpid()) + p.extension().string()))
      .string();
}

void CheckOutputPath(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw FileError(path, "is a folder, expected an output file");
  const fs::path parent = fs::path(path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw FileError(path, "output folder '" + parent.string() + "' does not exist");
}

void Commit(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw FileError(path, "cannot move the finished output into place: " + ec.message());
  }
}
}  // namespace

void WriteFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
  CheckOutputPath(path);
  const std::string tmp = TempPathFor(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw FileError(path, "cannot create output (is the folder writable?)");
    try {
      write(out);
      out.flush();
    } catch (...) {
      out.close();
      std::remove(tmp.c_str());
      throw;
    }
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw FileError(path, "write failed (disk full?)");
    }
  }
  Commit(tmp, path);
}

void WriteFileAtomicByName(const std::string& path, const std::function<void(const std::string&)>& write) {
  CheckOutputPath(path);
  const std::string tmp = TempPathFor(path);
  try {
    write(tmp);
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    throw FileError(path, std::string("write failed: ") + e.what());
  }
  std::error_code ec;
  if (!fs::exists(tmp, ec)) throw FileError(path, "writer produced no file");
  Commit(tmp, path);
}

bool LinkFileAtomic(const std::string& existing, const std::string& path) {
  CheckOutputPath(path);
  std::error_code ec;
  if (!fs::is_regular_file(existing, ec)) throw FileError(existing, "not a file to link to");
  if (fs::equivalent(existing, path, ec)) return true;
  const std::string tmp = TempPathFor(path);
  fs::remove(tmp, ec);
  fs::create_hard_link(existing, tmp, ec);
  if (ec) return false;
  Commit(tmp, path);
  return true;
}

std::string ReadFileBytes(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw FileError(path, "is a folder, expected a file");
  // A pipe or device has no size and cannot be opened at its end (the open
  // itself would fail): it is read as a stream.
  const bool regular = fs::is_regular_file(path, ec);
  std::ifstream in(path, regular ? std::ios::binary | std::ios::ate : std::ios::binary);
  if (!in) throw FileError(path, "cannot open for reading (missing or unreadable)");
  if (!regular) {
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // One allocation of the file's size: a growing stream buffer re-copies and
  // re-faults a 100 MB basis-image file a dozen times.
  const std::streamoff size = in.tellg();
  in.seekg(0);
  std::string bytes(size > 0 ? static_cast<size_t>(size) : 0, '\0');
  if (size > 0 && !in.read(bytes.data(), size)) throw FileError(path, "read failed");
  return bytes;
}

nlohmann::json ReadJsonFile(const std::string& path) {
  try {
    return nlohmann::json::parse(ReadFileBytes(path));
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("not JSON: ") + e.what());
  }
}

bool HasFormat(const nlohmann::json& j, const char* format) {
  if (!j.is_object()) return false;
  const auto it = j.find("format");
  return it != j.end() && it->is_string() && it->get<std::string>() == format;
}

}  // namespace brdfshot
