#include "util/jpeg_structure.h"

#include <cstring>

#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {
namespace {

// The first 0xFF at or after i (n when none): memchr, because the entropy-coded
// data of a 12 MP frame is megabytes long and walked once per frame.
size_t NextFF(const unsigned char* b, size_t i, size_t n) {
  if (i >= n) return n;
  const void* p = std::memchr(b + i, 0xFF, n - i);
  return p ? static_cast<size_t>(static_cast<const unsigned char*>(p) - b) : n;
}

}  // namespace

std::string JpegStructureProblem(const std::string& bytes) {
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  const size_t n = bytes.size();
  if (n < 4 || b[0] != 0xFF || b[1] != 0xD8) return "not a JPEG file (no start-of-image marker)";
  const std::string cut = "truncated: the file ends before its end-of-image marker (an interrupted copy?)";
  size_t i = 2;
  while (true) {
    i = NextFF(b, i, n);  // stray bytes between segments: libjpeg skips them too
    while (i < n && b[i] == 0xFF) ++i;  // fill bytes
    if (i >= n) return cut;
    const unsigned char marker = b[i++];
    if (marker == 0xD9) return "";                                     // end of image
    if ((marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) continue;  // markers without a length
    if (i + 2 > n) return cut;
    const size_t length = (static_cast<size_t>(b[i]) << 8) | b[i + 1];
    if (length < 2) return "a segment has an invalid length " + std::to_string(length);
    if (i + length > n) return cut;
    i += length;
    if (marker != 0xDA) continue;
    // Entropy-coded data after a start of scan: it runs to the next marker
    // that is neither a stuffed 0xFF00 nor a restart marker.
    while (true) {
      i = NextFF(b, i, n);
      if (i + 1 >= n) return cut;
      const unsigned char next = b[i + 1];
      if (next == 0x00 || (next >= 0xD0 && next <= 0xD7) || next == 0xFF) {
        i += next == 0xFF ? 1 : 2;
        continue;
      }
      break;
    }
  }
}

void CheckJpegComplete(const std::string& path) {
  const std::string problem = JpegStructureProblem(ReadFileBytes(path));
  if (!problem.empty()) throw FileError(path, problem);
}

}  // namespace brdfshot
