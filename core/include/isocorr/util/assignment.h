// Maximum-weight bipartite assignment (RAVAC's combining step, ravac.h).
#pragma once

#include <vector>

namespace isocorr {

// Assigns rows to distinct columns so that the sum of weight[row][column] is largest; a
// row gets -1 when rows outnumber columns and it is left over. O(n^3), n = max(rows, cols).
std::vector<int> max_weight_assignment(const std::vector<std::vector<double>>& weight);

}  // namespace isocorr
