#include "fit/database_cache.h"

#include <cstring>
#include <memory>
#include <fstream>
#include <nlohmann/json.hpp>

#include "util/atomic_file.h"
#include "util/check.h"
#include "util/huge_pages.h"
#include "util/mapped_file.h"

namespace brdfshot {

namespace {
constexpr char kMagic[8] = {'B', 'S', 'H', 'O', 'T', 'D', 'B', '1'};
constexpr const char* kFormat = "brdfshot-database-cache-3";
// B starts at a multiple of this in the file (the header is padded with
// spaces), so that a mapping of the file holds B at page alignment.
constexpr uint64_t kTableAlignment = 4096;
constexpr size_t kBlockRows = 16384;

std::string Hex(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// The cache file mapped into memory (util/mapped_file.h): reads copy out of
// the page cache, and B with every column kept is not copied at all.
// `whole`: the file is about to be read whole (B), so every page is mapped at
// once; the Gram matrices alone fault in only their pages.
class CacheFile {
 public:
  CacheFile(const std::string& path, bool whole)
      : path_(path), map_(std::make_shared<const MappedFile>(path, whole)) {}
  uint64_t Size() const { return map_->size(); }
  // The bytes [offset, offset + bytes); FileError if the file ends before.
  const unsigned char* At(uint64_t offset, uint64_t bytes) const {
    if (offset > Size() || bytes > Size() - offset) throw FileError(path_, "truncated");
    return map_->data() + offset;
  }
  void Read(void* dst, size_t bytes, uint64_t offset) const { std::memcpy(dst, At(offset, bytes), bytes); }
  const std::shared_ptr<const MappedFile>& mapping() const { return map_; }

 private:
  std::string path_;
  std::shared_ptr<const MappedFile> map_;
};

struct Layout {
  nlohmann::json header;
  uint64_t header_end = 0, gram_bytes = 0, rows = 0, cols = 0, blocks = 0;
  uint64_t gram_offset() const { return header_end; }
  uint64_t b_offset() const { return header_end + gram_bytes; }
  uint64_t checksum_offset() const { return b_offset() + rows * cols * sizeof(float); }
  uint64_t file_size() const { return checksum_offset() + (2 + blocks) * sizeof(uint64_t); }
};

// Reads and checks everything but B's blocks: magic, header, the id it names,
// the file's length and the header's checksum.
Layout ReadLayout(const CacheFile& f, const std::string& path, const CachedDatabaseId& id,
                  std::vector<uint64_t>* checksums) {
  const uint64_t size = f.Size();
  char magic[8];
  uint64_t header_bytes = 0;
  if (size < 16) throw FileError(path, "truncated database cache");
  f.Read(magic, 8, 0);
  f.Read(&header_bytes, 8, 8);
  if (std::memcmp(magic, kMagic, 8) != 0) throw FileError(path, "not a brdfshot database cache (bad magic)");
  if (header_bytes > size - 16) throw FileError(path, "truncated header");
  std::string text(header_bytes, '\0');
  f.Read(text.data(), header_bytes, 16);
  Layout l;
  try {
    l.header = nlohmann::json::parse(text);
    if (l.header.at("format") != kFormat)
      throw FileError(path, "another cache format (" + l.header.at("format").dump() + ")");
    const auto g = l.header.at("grid");
    if (l.header.at("kind") != id.kind || l.header.at("fingerprint") != id.fingerprint ||
        !(MerlGrid{g.at(0), g.at(1), g.at(2)} == id.grid))
      throw FileError(path, "is the cache of another database or source version");
    l.rows = l.header.at("rows");
    l.cols = l.header.at("cols");
    if (l.header.at("block_rows") != kBlockRows) throw FileError(path, "another block size");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("damaged header: ") + e.what());
  }
  if (l.rows != id.grid.size() || l.cols == 0 || l.cols != 3 * l.header["materials"].size())
    throw FileError(path, "header sizes do not match its grid and materials");
  l.header_end = 16 + header_bytes;
  l.gram_bytes = 2 * l.cols * l.cols * sizeof(double);
  l.blocks = (l.rows + kBlockRows - 1) / kBlockRows;
  if (size != l.file_size())
    throw FileError(path, "is " + std::to_string(size) + " bytes, its header says " + std::to_string(l.file_size()) +
                              " (truncated or damaged)");
  checksums->resize(2 + l.blocks);
  f.Read(checksums->data(), checksums->size() * sizeof(uint64_t), l.checksum_offset());
  if (Checksum64(text.data(), text.size()) != (*checksums)[0]) throw FileError(path, "header checksum mismatch");
  return l;
}

std::vector<std::string> Names(const nlohmann::json& header, const char* key) {
  return header.contains(key) ? header[key].get<std::vector<std::string>>() : std::vector<std::string>{};
}

// The names of materials `keep` (and their families, when the cache has them).
void SelectNames(const nlohmann::json& header, const std::vector<int>& keep, const std::string& path,
                 std::vector<std::string>* materials, std::vector<std::string>* families) {
  const std::vector<std::string> names = Names(header, "materials"), fams = Names(header, "families");
  for (int m : keep) {
    if (m < 0 || static_cast<size_t>(m) >= names.size()) throw FileError(path, "lists fewer materials than its source");
    materials->push_back(names[m]);
    if (!fams.empty()) families->push_back(fams.at(m));
  }
}

// Every column of B, as a view of the mapped file; each block is checked
// against its checksum first (B is read once, from the page cache where the
// file is there already).
BasisTables MapTables(const CacheFile& f, const std::string& path, const Layout& l,
                      const std::vector<uint64_t>& sums) {
  const auto* b = reinterpret_cast<const float*>(f.At(l.b_offset(), l.rows * l.cols * sizeof(float)));
  bool damaged = false;
#pragma omp parallel for schedule(dynamic, 2)
  for (long k = 0; k < static_cast<long>(l.blocks); ++k) {
    const uint64_t r0 = k * kBlockRows, n = std::min<uint64_t>(kBlockRows, l.rows - r0);
    if (Checksum64(b + r0 * l.cols, n * l.cols * sizeof(float)) != sums[2 + k]) {
#pragma omp atomic write
      damaged = true;
    }
  }
  if (damaged) throw FileError(path, "table checksum mismatch (damaged)");
  return BasisTables(f.mapping(), b, static_cast<Eigen::Index>(l.rows), static_cast<Eigen::Index>(l.cols));
}

std::vector<int> Columns(const std::vector<int>& keep) {
  std::vector<int> cols;
  for (int m : keep)
    for (int c = 0; c < 3; ++c) cols.push_back(3 * m + c);
  return cols;
}
}  // namespace

std::string CachedDatabaseId::FileName() const {
  return kind + "-" + std::to_string(grid.n_th) + "x" + std::to_string(grid.n_td) + "x" + std::to_string(grid.n_pd) +
         "-" + fingerprint + ".bsdb";
}

namespace {
// Interleaved multiply-xor lanes, each an independent chain: the compiler
// keeps many in vector registers, and 32 check 7.8 GB/s of one core of the
// 2-core VM against 3.9 GB/s for 4 (docs/benchmarks.md). Lane k starts from
// seed k mod 4, moved by k / 4, so the first four lanes start where a
// 4-lane checksum does.
template <int kLanes>
uint64_t LaneChecksum(const void* data, size_t bytes) {
  constexpr uint64_t kMul = 0x9E3779B97F4A7C15ull;
  constexpr uint64_t kSeed[4] = {0x243F6A8885A308D3ull, 0x13198A2E03707344ull, 0xA4093822299F31D0ull,
                                 0x082EFA98EC4E6C89ull};
  uint64_t lane[kLanes];
  for (int k = 0; k < kLanes; ++k) lane[k] = kSeed[k % 4] ^ (static_cast<uint64_t>(k / 4) * kMul);
  const auto* p = static_cast<const unsigned char*>(data);
  size_t i = 0;
  for (; i + 8 * kLanes <= bytes; i += 8 * kLanes) {
    uint64_t w[kLanes];
    std::memcpy(w, p + i, sizeof w);
    for (int k = 0; k < kLanes; ++k) {
      lane[k] = (lane[k] ^ w[k]) * kMul;
      lane[k] ^= lane[k] >> 29;
    }
  }
  uint64_t h = bytes * kMul;
  for (; i < bytes; ++i) h = (h ^ p[i]) * kMul;
  for (uint64_t v : lane) h = ((h ^ v) * kMul) ^ (h >> 31);
  return h;
}
}  // namespace

uint64_t Checksum64(const void* data, size_t bytes) { return LaneChecksum<32>(data, bytes); }

// Four lanes: a fingerprint names a cache file, so it stays what it is
// whatever the cache's format, and a cache of another format is found at its
// path and rebuilt there instead of being left beside the new one.
std::string FingerprintFiles(const std::vector<std::string>& files, const std::string& salt) {
  uint64_t h = LaneChecksum<4>(salt.data(), salt.size());
  for (const std::string& f : files) {
    const std::string bytes = ReadFileBytes(f);
    const uint64_t parts[2] = {h, LaneChecksum<4>(bytes.data(), bytes.size())};
    h = LaneChecksum<4>(parts, sizeof parts);
  }
  return Hex(h);
}

void WriteDatabaseCache(const std::string& path, const CachedDatabaseId& id, const BasisDatabase& db,
                        const Eigen::MatrixXd& gram, const Eigen::MatrixXd& gram_cos) {
  const uint64_t rows = static_cast<uint64_t>(db.B.rows()), cols = static_cast<uint64_t>(db.B.cols());
  BRDFSHOT_CHECK(rows == db.grid.size() && gram.rows() == static_cast<Eigen::Index>(cols) &&
                 gram_cos.rows() == static_cast<Eigen::Index>(cols));
  nlohmann::json h = {{"format", kFormat},
                      {"kind", id.kind},
                      {"label", db.label},
                      {"grid", {db.grid.n_th, db.grid.n_td, db.grid.n_pd}},
                      {"fingerprint", id.fingerprint},
                      {"rows", rows},
                      {"cols", cols},
                      {"block_rows", kBlockRows},
                      {"materials", db.materials}};
  if (!db.families.empty()) h["families"] = db.families;
  std::string text = h.dump();
  const uint64_t gram_bytes = 2 * cols * cols * sizeof(double);
  const uint64_t b_offset = 16 + text.size() + gram_bytes;
  text.append((kTableAlignment - b_offset % kTableAlignment) % kTableAlignment, ' ');
  const uint64_t header_bytes = text.size();
  const uint64_t blocks = (rows + kBlockRows - 1) / kBlockRows;
  std::vector<uint64_t> sums(2 + blocks);
  sums[0] = Checksum64(text.data(), text.size());
  std::vector<double> grams(2 * cols * cols);
  Eigen::Map<Eigen::MatrixXd>(grams.data(), cols, cols) = gram;
  Eigen::Map<Eigen::MatrixXd>(grams.data() + cols * cols, cols, cols) = gram_cos;
  sums[1] = Checksum64(grams.data(), grams.size() * sizeof(double));
#pragma omp parallel for schedule(dynamic, 4)
  for (long b = 0; b < static_cast<long>(blocks); ++b) {
    const uint64_t r0 = b * kBlockRows, n = std::min<uint64_t>(kBlockRows, rows - r0);
    sums[2 + b] = Checksum64(db.B.data() + r0 * cols, n * cols * sizeof(float));
  }
  WriteFileAtomic(path, [&](std::ostream& o) {
    o.write(kMagic, 8);
    o.write(reinterpret_cast<const char*>(&header_bytes), 8);
    o.write(text.data(), static_cast<std::streamsize>(text.size()));
    o.write(reinterpret_cast<const char*>(grams.data()), static_cast<std::streamsize>(grams.size() * sizeof(double)));
    o.write(reinterpret_cast<const char*>(db.B.data()), static_cast<std::streamsize>(rows * cols * sizeof(float)));
    o.write(reinterpret_cast<const char*>(sums.data()), static_cast<std::streamsize>(sums.size() * sizeof(uint64_t)));
  });
}

BasisDatabase ReadDatabaseCache(const std::string& path, const CachedDatabaseId& id, const std::vector<int>& keep) {
  const CacheFile f(path, true);
  std::vector<uint64_t> sums;
  const Layout l = ReadLayout(f, path, id, &sums);
  BasisDatabase db;
  db.kind = id.kind;
  db.grid = id.grid;
  db.label = l.header.value("label", "");
  SelectNames(l.header, keep, path, &db.materials, &db.families);
  const std::vector<int> cols = Columns(keep);
  bool all = cols.size() == l.cols;  // every column, in the file's order
  for (size_t k = 0; all && k < cols.size(); ++k) all = cols[k] == static_cast<int>(k);
  if (all && l.b_offset() % alignof(float) == 0) {
    db.B = MapTables(f, path, l, sums);
    return db;
  }
  MatrixXfR B(static_cast<Eigen::Index>(l.rows), static_cast<Eigen::Index>(cols.size()));
  AdviseHugePages(B.data(), sizeof(float) * B.size());
  bool damaged = false;
#pragma omp parallel
  {
    std::vector<float> buffer(all ? 0 : kBlockRows * l.cols);
#pragma omp for schedule(dynamic, 2)
    for (long b = 0; b < static_cast<long>(l.blocks); ++b) {
      const uint64_t r0 = b * kBlockRows, n = std::min<uint64_t>(kBlockRows, l.rows - r0);
      // With every column kept the block lands in B directly; else it is read
      // whole (the checksum covers whole blocks) and its kept columns copied.
      float* dst = all ? B.data() + r0 * l.cols : buffer.data();
      const size_t bytes = n * l.cols * sizeof(float);
      bool ok = true;
      try {  // no exception may leave an OpenMP loop
        f.Read(dst, bytes, l.b_offset() + r0 * l.cols * sizeof(float));
      } catch (const Error&) {
        ok = false;
      }
      if (!ok || Checksum64(dst, bytes) != sums[2 + b]) {
#pragma omp atomic write
        damaged = true;
        continue;
      }
      if (!all)
        for (uint64_t r = 0; r < n; ++r)
          for (size_t k = 0; k < cols.size(); ++k) B(r0 + r, k) = buffer[r * l.cols + cols[k]];
    }
  }
  if (damaged) throw FileError(path, "table checksum mismatch (damaged)");
  db.B = BasisTables(std::move(B));
  return db;
}

DatabaseGrams ReadDatabaseCacheGrams(const std::string& path, const CachedDatabaseId& id,
                                     const std::vector<int>& keep) {
  const CacheFile f(path, false);
  std::vector<uint64_t> sums;
  const Layout l = ReadLayout(f, path, id, &sums);
  std::vector<double> grams(2 * l.cols * l.cols);
  f.Read(grams.data(), grams.size() * sizeof(double), l.gram_offset());
  if (Checksum64(grams.data(), grams.size() * sizeof(double)) != sums[1])
    throw FileError(path, "Gram checksum mismatch (damaged)");
  DatabaseGrams g;
  g.kind = id.kind;
  g.grid = id.grid;
  g.label = l.header.value("label", "");
  SelectNames(l.header, keep, path, &g.materials, &g.families);
  const std::vector<int> cols = Columns(keep);
  const Eigen::Index n = static_cast<Eigen::Index>(l.cols);
  g.gram = Eigen::Map<const Eigen::MatrixXd>(grams.data(), n, n)(cols, cols);
  g.gram_cos = Eigen::Map<const Eigen::MatrixXd>(grams.data() + n * n, n, n)(cols, cols);
  return g;
}

}  // namespace brdfshot
