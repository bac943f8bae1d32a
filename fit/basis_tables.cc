#include "fit/basis_tables.h"

#include <new>
#include <utility>

namespace brdfshot {

BasisTables::BasisTables(MatrixXfR tables) : Base(nullptr, 0, 0) {
  auto owned = std::make_shared<const MatrixXfR>(std::move(tables));
  // An Eigen::Map is re-seated by constructing it again in place (Eigen's
  // documented way; its destructor is trivial).
  new (static_cast<Base*>(this)) Base(owned->data(), owned->rows(), owned->cols());
  storage_ = std::move(owned);
}

BasisTables::BasisTables(std::shared_ptr<const void> storage, const float* data, Eigen::Index rows,
                         Eigen::Index cols)
    : Base(data, rows, cols), storage_(std::move(storage)), mapped_(true) {}

BasisTables& BasisTables::operator=(const BasisTables& other) {
  if (this == &other) return *this;
  new (static_cast<Base*>(this)) Base(other.data(), other.rows(), other.cols());
  storage_ = other.storage_;
  mapped_ = other.mapped_;
  return *this;
}

}  // namespace brdfshot
