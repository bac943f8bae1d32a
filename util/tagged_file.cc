#include "util/tagged_file.h"

#include <cstdint>
#include <cstring>

#include "util/atomic_file.h"
#include "util/check.h"

namespace brdfshot {

void WriteTaggedFile(const std::string& path, const char (&magic)[8], const nlohmann::json& header,
                     const std::function<void(std::ostream&)>& body) {
  const std::string hs = header.dump();
  WriteFileAtomic(path, [&](std::ostream& out) {
    out.write(magic, 8);
    const uint64_t len = hs.size();
    out.write(reinterpret_cast<const char*>(&len), 8);
    out.write(hs.data(), hs.size());
    body(out);
  });
}

TaggedHeader ParseTaggedHeader(std::string_view bytes, const char (&magic)[8], const std::string& kind,
                               const std::string& name) {
  if (bytes.size() < 16 || std::memcmp(bytes.data(), magic, 8) != 0)
    throw FileError(name, "not a brdfshot " + kind + " (bad magic)");
  uint64_t len;
  std::memcpy(&len, bytes.data() + 8, 8);
  if (len > bytes.size() - 16) throw FileError(name, "truncated header");
  TaggedHeader t;
  try {
    t.header = nlohmann::json::parse(bytes.substr(16, len));
  } catch (const nlohmann::json::exception& e) {
    throw FileError(name, std::string("bad JSON header: ") + e.what());
  }
  t.body_offset = 16 + len;
  return t;
}

}  // namespace brdfshot
