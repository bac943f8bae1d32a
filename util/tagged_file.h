// The project's binary cache files (basis images, observations) share one
// frame: an 8-byte magic naming the kind, a uint64 length, a JSON header of
// that length (provenance and sizes), then the body. One writer and one
// header parser, so both kinds reject bad magic and truncation alike.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <string_view>

namespace brdfshot {

// Writes magic, header and `body(stream)` atomically (WriteFileAtomic).
void WriteTaggedFile(const std::string& path, const char (&magic)[8], const nlohmann::json& header,
                     const std::function<void(std::ostream&)>& body);

struct TaggedHeader {
  nlohmann::json header;
  size_t body_offset = 0;  // where the body starts in the bytes
};

// Error naming `name`: "not a brdfshot <kind> (bad magic)", "truncated header",
// "bad JSON header: ...".
TaggedHeader ParseTaggedHeader(std::string_view bytes, const char (&magic)[8], const std::string& kind,
                               const std::string& name);

}  // namespace brdfshot
