// The database's tables evaluated once per machine. Sampling MERL's 100 neural
// fits onto the full MERL grid is 1.46 M bins × 100 networks, seconds of work
// that every command needing the tables (basis, cluster, fit, render, eval)
// would otherwise repeat. The cache keeps the full database — every material
// of the source, in the source's order — in one file:
//
//   "BSHOTDB1" | uint64 header bytes | JSON header, padded with spaces so
//   that B starts at a multiple of 4096 bytes
//   | float64 BᵀB (n × n) | float64 Bᵀdiag(cos²)B (n × n)
//   | float32 B (bins × n, row-major, as BasisDatabase::B)
//   | uint64 checksums: header, Gram section, then one per block of B rows
//
// The header records the format, the kind, label, grid, material names (and
// families), the source's fingerprint and the block size. A file that is short,
// has another header or fingerprint, or fails a checksum is not a cache of this
// database: the reader throws FileError naming it, and LoadDatabase rebuilds it.
// Files are written atomically, so a crash never leaves half a cache.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fit/database.h"

namespace brdfshot {

struct CachedDatabaseId {
  std::string kind;  // nbrdf | standin
  MerlGrid grid;
  std::string fingerprint;       // hex digest of the source files' bytes and the evaluator version
  std::string FileName() const;  // "<kind>-<grid>-<fingerprint>.bsdb"
};

// Digest of `files`' bytes (in order) and `salt`; Error naming an unreadable file.
std::string FingerprintFiles(const std::vector<std::string>& files, const std::string& salt);

// 64-bit checksum of a byte range (32 interleaved multiply-xor lanes, so it
// runs near memory speed; detects any changed, swapped or truncated word).
uint64_t Checksum64(const void* data, size_t bytes);

// Writes `db` (all materials of the source) with its Gram matrices to `path`.
void WriteDatabaseCache(const std::string& path, const CachedDatabaseId& id, const BasisDatabase& db,
                        const Eigen::MatrixXd& gram, const Eigen::MatrixXd& gram_cos);

// Reads the columns of materials `keep` (indices into the cached list) of B.
// Every block read is checked. With every material kept, in the file's order,
// B is a view of the file mapped into memory (BasisTables::mapped()), not a
// copy. FileError naming `path` if it is not a sound cache of `id`.
BasisDatabase ReadDatabaseCache(const std::string& path, const CachedDatabaseId& id, const std::vector<int>& keep);

// Only the header and the Gram matrices, restricted to `keep` (cheap: B is not
// read, but the file's length is checked).
DatabaseGrams ReadDatabaseCacheGrams(const std::string& path, const CachedDatabaseId& id, const std::vector<int>& keep);

}  // namespace brdfshot
