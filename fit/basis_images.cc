#include "fit/basis_images.h"

#include <cmath>
#include <cstring>
#include <filesystem>

#include "util/atomic_file.h"
#include "util/check.h"
#include "util/huge_pages.h"
#include "util/json_int.h"
#include "util/mapped_file.h"
#include "util/tagged_file.h"

namespace brdfshot {

namespace {
constexpr char kMagic[8] = {'B', 'S', 'H', 'O', 'T', 'B', 'I', '1'};
}

MerlGrid BasisImages::Grid() const {
  const auto& g = header.at("grid");
  return MerlGrid{g.at(0), g.at(1), g.at(2)};
}

std::vector<std::string> BasisImages::BasisNames() const { return header.at("bases").get<std::vector<std::string>>(); }

LambertGgxLobes BasisImages::Lobes(const std::string& source) const {
  if (!has_lobes() || !header.contains("lobes")) throw FileError(source, "holds no analytic lobe images");
  LambertGgxLobes l = LambertGgxLobes::FromJson(header.at("lobes"), source);
  if (l.columns() != lobes[0].cols()) throw FileError(source, "lobe description does not match its lobe images");
  return l;
}

void BasisImages::Write(const std::string& path) const {
  const size_t P = geometry.size(), n = Y[0].cols(), nl = lobes[0].cols();
  BRDFSHOT_CHECK(static_cast<size_t>(Y[0].rows()) == P);
  BRDFSHOT_CHECK(nl == 0 || (static_cast<size_t>(lobes[0].rows()) == P && header.contains("lobes")),
                 "lobe images need their description in the header");
  nlohmann::json h = header;
  h["pixels"] = P;
  h["num_bases"] = n;
  if (nl > 0) h["num_lobes"] = nl;
  h["width"] = geometry.width;
  h["height"] = geometry.height;
  WriteTaggedFile(path, kMagic, h, [&](std::ostream& out) {
    for (size_t p = 0; p < P; ++p) {
      const int32_t xy[2] = {geometry.x[p], geometry.y[p]};
      out.write(reinterpret_cast<const char*>(xy), 8);
    }
    for (size_t p = 0; p < P; ++p) {
      const double v[6] = {geometry.normal[p].x, geometry.normal[p].y, geometry.normal[p].z,
                           geometry.view[p].x,   geometry.view[p].y,   geometry.view[p].z};
      out.write(reinterpret_cast<const char*>(v), sizeof v);
    }
    for (int c = 0; c < 3; ++c) out.write(reinterpret_cast<const char*>(Y[c].data()), P * n * 4);
    for (int c = 0; c < 3 && nl > 0; ++c) out.write(reinterpret_cast<const char*>(lobes[c].data()), P * nl * 4);
  });
}

BasisImages BasisImages::Read(const std::string& path) {
  // A regular file is mapped rather than read into a string: it is 100-odd MB
  // and is copied into the images once; a string would cost a second copy and
  // the zeroing of its fresh pages (util/mapped_file.h). A pipe or other
  // stream has no size to map, so it is read.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return Parse(ReadFileBytes(path), path);
  const MappedFile file(path, /*populate=*/true);
  return Parse(std::string_view(reinterpret_cast<const char*>(file.data()), file.size()), path);
}

BasisImages BasisImages::Parse(std::string_view bytes, const std::string& name) {
  TaggedHeader t = ParseTaggedHeader(bytes, kMagic, "basis-image file", name);
  BasisImages b;
  b.header = std::move(t.header);
  uint64_t P, n, nl = 0;
  try {
    P = static_cast<uint64_t>(JsonInt(b.header, "pixels", 0, 1 << 28, name));
    n = static_cast<uint64_t>(JsonInt(b.header, "num_bases", 0, 100000, name));
    if (b.header.contains("num_lobes")) nl = static_cast<uint64_t>(JsonInt(b.header, "num_lobes", 1, 10000, name));
    b.geometry.width = static_cast<int>(JsonInt(b.header, "width", 1, 1 << 20, name));
    b.geometry.height = static_cast<int>(JsonInt(b.header, "height", 1, 1 << 20, name));
    if (b.header.at("bases").size() != n) throw FileError(name, "basis names do not match num_bases");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(name, std::string("incomplete header: ") + e.what());
  }
  const uint64_t need = t.body_offset + P * 8 + P * 48 + 3 * P * (n + nl) * 4;
  if (bytes.size() != need)
    throw FileError(name, "size " + std::to_string(bytes.size()) + " does not match header (needs " +
                              std::to_string(need) + "): truncated or corrupt");
  const char* p = bytes.data() + t.body_offset;
  b.geometry.x.resize(P);
  b.geometry.y.resize(P);
  for (size_t i = 0; i < P; ++i) {
    int32_t xy[2];
    std::memcpy(xy, p + 8 * i, 8);
    b.geometry.x[i] = xy[0];
    b.geometry.y[i] = xy[1];
  }
  p += 8 * P;
  b.geometry.normal.reserve(P);
  b.geometry.view.reserve(P);
  for (size_t i = 0; i < P; ++i) {
    double v[6];
    std::memcpy(v, p + 48 * i, 48);
    b.geometry.normal.push_back(Vec3(v[0], v[1], v[2]));
    b.geometry.view.push_back(Vec3(v[3], v[4], v[5]));
  }
  p += 48 * P;
  for (int c = 0; c < 3; ++c) {
    b.Y[c].resize(P, n);
    // 100-odd MB of fresh pages: on huge pages their first touch is a few
    // dozen faults, not tens of thousands (util/huge_pages.h).
    AdviseHugePages(b.Y[c].data(), sizeof(float) * b.Y[c].size());
    std::memcpy(b.Y[c].data(), p, P * n * 4);
    p += P * n * 4;
    if (!b.Y[c].allFinite()) throw FileError(name, "basis images contain NaN or Inf");
  }
  for (int c = 0; c < 3 && nl > 0; ++c) {
    b.lobes[c].resize(P, nl);
    AdviseHugePages(b.lobes[c].data(), sizeof(float) * b.lobes[c].size());
    std::memcpy(b.lobes[c].data(), p, P * nl * 4);
    p += P * nl * 4;
    if (!b.lobes[c].allFinite()) throw FileError(name, "lobe images contain NaN or Inf");
  }
  if (nl > 0) b.Lobes(name);  // the description must match the images
  return b;
}

nlohmann::json BasisImagesHeader(const LatLongProbe& probe, const PixelGeometry& geometry, const std::string& quality,
                                 const BasisDatabase& db, const std::vector<std::string>& basis_names) {
  return {{"format", "brdfshot-basis-images-1"},
          {"probe_name", probe.name()},
          {"probe_hash", probe.Hash()},
          {"probe_size", {probe.width(), probe.height()}},
          {"geometry_hash", geometry.Hash()},
          {"quality", quality},
          {"database", db.label},
          {"database_kind", db.kind},
          {"grid", {db.grid.n_th, db.grid.n_td, db.grid.n_pd}},
          {"bases", basis_names}};
}

}  // namespace brdfshot
