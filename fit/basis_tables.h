// The database's tables, bins × bases, as a read-only row-major float matrix
// (the layout of MatrixXfR), held either in memory of their own or as a view
// of a database cache mapped from disk (util/mapped_file.h).
//
// Why a type of its own: MERL's full grid is 1.75 GB of tables, and reading
// them from the cache into fresh memory costs most of a `fit` or `basis`
// command (docs/benchmarks.md); a mapping of the cache costs nothing to open.
// Both kinds read alike, as an Eigen::Map, so code that reads tables takes
// `const TablesRef&` and never knows which it has. Copies share the storage:
// the tables never change once made.
#pragma once

#include <memory>

#include "util/eigen_types.h"

namespace brdfshot {

// What functions that only read tables take: a MatrixXfR, a BasisTables or a
// block of either, without a copy. Rows are contiguous, but a block of
// columns has outerStride() > cols(): pointer arithmetic uses outerStride().
using TablesRef = Eigen::Ref<const MatrixXfR>;
// A TablesRef kept past the call that gave it (what it views must outlive it).
using TablesMap = Eigen::Map<const MatrixXfR, 0, Eigen::OuterStride<>>;
inline TablesMap MapOf(const TablesRef& t) {
  return TablesMap(t.data(), t.rows(), t.cols(), Eigen::OuterStride<>(t.outerStride()));
}

class BasisTables : public Eigen::Map<const MatrixXfR> {
 public:
  using Base = Eigen::Map<const MatrixXfR>;

  BasisTables() : Base(nullptr, 0, 0) {}
  // Takes `tables` over.
  explicit BasisTables(MatrixXfR tables);
  // A view of `rows` × `cols` floats at `data` inside a mapped file, which
  // `storage` keeps alive (a MappedFile, or what owns one).
  BasisTables(std::shared_ptr<const void> storage, const float* data, Eigen::Index rows, Eigen::Index cols);

  BasisTables(const BasisTables& other)
      : Base(other.data(), other.rows(), other.cols()), storage_(other.storage_), mapped_(other.mapped_) {}
  BasisTables& operator=(const BasisTables& other);

  // Whether the tables are a view of a mapped file rather than memory of their own.
  bool mapped() const { return mapped_; }

 private:
  std::shared_ptr<const void> storage_;
  bool mapped_ = false;
};

}  // namespace brdfshot
