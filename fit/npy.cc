#include "fit/npy.h"

#include <cstdint>
#include <cstring>
#include <regex>

#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {

NpyArray ParseNpyFloat32(const std::string& bytes, const std::string& name) {
  static const char kMagic[] = "\x93NUMPY";
  if (bytes.size() < 10 || std::memcmp(bytes.data(), kMagic, 6) != 0)
    throw FileError(name, "not a NumPy .npy file (bad magic)");
  if (bytes[6] != 1 || bytes[7] != 0)
    throw FileError(name, "unsupported .npy version " + std::to_string(int(bytes[6])) + "." +
                              std::to_string(int(bytes[7])) + " (expected 1.0)");
  const size_t header_len =
      static_cast<unsigned char>(bytes[8]) | (static_cast<size_t>(static_cast<unsigned char>(bytes[9])) << 8);
  if (10 + header_len > bytes.size()) throw FileError(name, "truncated .npy header");
  const std::string header = bytes.substr(10, header_len);
  std::smatch m;
  if (!std::regex_search(header, m, std::regex("'descr'\\s*:\\s*'([^']*)'")))
    throw FileError(name, ".npy header has no dtype");
  if (m[1] != "<f4") throw FileError(name, "dtype '" + m[1].str() + "', expected '<f4' (float32)");
  if (!std::regex_search(header, m, std::regex("'fortran_order'\\s*:\\s*(True|False)")) || m[1] != "False")
    throw FileError(name, "not in C order (fortran_order must be False)");
  if (!std::regex_search(header, m, std::regex("'shape'\\s*:\\s*\\(([^)]*)\\)")))
    throw FileError(name, ".npy header has no shape");
  NpyArray a;
  size_t count = 1;
  const std::string dims = m[1];
  std::regex num("\\d+");
  for (auto it = std::sregex_iterator(dims.begin(), dims.end(), num); it != std::sregex_iterator(); ++it) {
    const std::string tok = it->str();
    if (tok.size() > 9) throw FileError(name, "absurd .npy shape");
    a.shape.push_back(std::stoul(tok));
    count *= a.shape.back();
    if (count > (1u << 28)) throw FileError(name, "absurd .npy shape");
  }
  const size_t offset = 10 + header_len;
  if (bytes.size() - offset != count * sizeof(float))
    throw FileError(name, "data is " + std::to_string(bytes.size() - offset) + " bytes, shape needs " +
                              std::to_string(count * sizeof(float)) + " (truncated?)");
  a.data.resize(count);
  std::memcpy(a.data.data(), bytes.data() + offset, count * sizeof(float));
  return a;
}

NpyArray ReadNpyFloat32(const std::string& path) { return ParseNpyFloat32(ReadFileBytes(path), path); }

}  // namespace brdfshot
