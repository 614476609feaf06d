#include "isocorr/util/assignment.h"

#include <algorithm>
#include <limits>

namespace isocorr {

// Hungarian method with potentials on the negated weights, on the matrix padded to a
// square with zero weights.
std::vector<int> max_weight_assignment(const std::vector<std::vector<double>>& weight) {
  const int rows = static_cast<int>(weight.size());
  const int cols = rows ? static_cast<int>(weight[0].size()) : 0;
  const int n = std::max(rows, cols);  // square, padded with zero weights
  auto cost = [&](int r, int c) { return r < rows && c < cols ? -weight[r][c] : 0.0; };
  const double inf = std::numeric_limits<double>::max();
  // 1-based: column 0 is the virtual start of each augmenting path.
  std::vector<double> row_potential(n + 1, 0), col_potential(n + 1, 0);
  std::vector<int> row_of(n + 1, 0), previous(n + 1, 0);
  for (int r = 1; r <= n; ++r) {
    row_of[0] = r;
    int col = 0;
    std::vector<double> slack(n + 1, inf);
    std::vector<char> visited(n + 1, 0);
    do {
      visited[col] = 1;
      const int row = row_of[col];
      double delta = inf;
      int next = 0;
      for (int c = 1; c <= n; ++c) {
        if (visited[c]) continue;
        const double reduced = cost(row - 1, c - 1) - row_potential[row] - col_potential[c];
        if (reduced < slack[c]) slack[c] = reduced, previous[c] = col;
        if (slack[c] < delta) delta = slack[c], next = c;
      }
      for (int c = 0; c <= n; ++c) {
        if (visited[c]) row_potential[row_of[c]] += delta, col_potential[c] -= delta;
        else slack[c] -= delta;
      }
      col = next;
    } while (row_of[col] != 0);
    do {  // flip the augmenting path
      const int before = previous[col];
      row_of[col] = row_of[before];
      col = before;
    } while (col != 0);
  }
  std::vector<int> assignment(rows, -1);
  for (int c = 1; c <= n; ++c)
    if (row_of[c] >= 1 && row_of[c] <= rows && c <= cols) assignment[row_of[c] - 1] = c - 1;
  return assignment;
}

}  // namespace isocorr
