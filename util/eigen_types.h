// Eigen types shared by every stage.
#pragma once

#include <Eigen/Core>

namespace brdfshot {

// Row-major float: one row per pixel or per bin, so a row is contiguous — the
// layout the transport writes and the tables are streamed in.
using MatrixXfR = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// Row-major double: rows of a table taken in double (e.g. constrained bins),
// built and read a row at a time.
using MatrixXdR = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace brdfshot
