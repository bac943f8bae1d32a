// Outputs are written to "<path>.tmp.<pid>" and renamed into place, so a crash or
// a full disk never leaves a half-written file where a Makefile expects a result,
// and an input is never truncated by a typo that names it as output.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

namespace brdfshot {

// Calls `write(stream)` on a temporary beside `path`, then renames it over `path`.
// Throws brdfshot::Error naming `path` if the folder is not writable or the write
// fails; the temporary is removed on every failure.
void WriteFileAtomic(const std::string& path, const std::function<void(std::ostream&)>& write);

// For writers that need a file name (OpenEXR, OpenCV): `write(tmp_path)` must
// create tmp_path; it is renamed onto `path` on success and removed on failure.
// The temporary keeps `path`'s extension so format-by-extension writers work.
void WriteFileAtomicByName(const std::string& path, const std::function<void(const std::string&)>& write);

// Makes `path` a hard link to the finished file `existing` (a temporary link
// beside `path`, renamed into place): the same bytes without writing them
// again. Returns false and leaves `path` alone where the file system refuses
// the link (another device, no hard links), so the caller writes instead;
// true without change when `path` already is `existing`. The two names share
// one inode, so this suits outputs that are only ever replaced whole, as every
// output here is.
bool LinkFileAtomic(const std::string& existing, const std::string& path);

// Reads a whole file; Error naming the file if it cannot be opened or is a folder.
std::string ReadFileBytes(const std::string& path);

// A whole JSON file (sidecars, class models, calibrations); Error naming the
// file if it cannot be read or is not JSON.
nlohmann::json ReadJsonFile(const std::string& path);

// Whether `j` is an object whose "format" is the string `format` (false for
// any other shape, never an exception).
bool HasFormat(const nlohmann::json& j, const char* format);

}  // namespace brdfshot
