// Eigen types shared by every stage.
#pragma once

#include <Eigen/Core>

namespace brdfshot {

// Row-major float: one row per pixel or per bin, so a row is contiguous — the
// layout the transport writes and the tables are streamed in.
using MatrixXfR = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

}  // namespace brdfshot
