// A tall matrix times a small square-ish one, by chunks of rows.
//
// Eigen packs the whole left side of a product it blocks by columns (200 basis columns are
// two blocks): at 52K vertices a fresh buffer of the left side's size (167 MiB for the
// Ritz vectors), whose pages the kernel zeroes one by one, and a product assigned to its
// own operand needs a second basis-sized matrix besides. Chunks of a multiple of Eigen's
// row panel (24 rows for double with AVX-512, 12 with AVX2: 3072 is a multiple of each)
// give the same bits as one product.
#pragma once

#include <algorithm>

#include <Eigen/Core>

namespace isocorr {

inline constexpr Eigen::Index kProductRows = 3072;

// out = lhs * rhs, out already lhs.rows() x rhs.cols(); out may be lhs itself (in place).
template <class Lhs, class Out>
void multiply_by_row_chunks(const Lhs& lhs, const Eigen::MatrixXd& rhs, Out& out) {
  Eigen::MatrixXd rows;
  for (Eigen::Index begin = 0; begin < lhs.rows(); begin += kProductRows) {
    const Eigen::Index count = std::min(kProductRows, lhs.rows() - begin);
    rows.noalias() = lhs.middleRows(begin, count) * rhs;
    out.middleRows(begin, count) = rows;
  }
}

}  // namespace isocorr
