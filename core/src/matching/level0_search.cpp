#include "isocorr/matching/level0_search.h"

#include <algorithm>
#include <cmath>

#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Depth-first enumeration of injective maps with an exact lower-bound prune.
class Enumerator {
 public:
  Enumerator(const Eigen::MatrixXd& s, const Eigen::MatrixXd& t, double max_sum)
      : s_(s), t_(t), m_(static_cast<int>(s.rows())), m_prime_(static_cast<int>(t.rows())),
        max_sum_(max_sum), target_of_(m_, -1), used_(m_prime_, 0) {}

  void run_from(int first_target, std::vector<Level0Map>& out) {
    target_of_[0] = first_target;
    used_[first_target] = 1;
    extend(1, 0.0, out);
    used_[first_target] = 0;
  }

 private:
  void extend(int depth, double sum, std::vector<Level0Map>& out) {
    if (depth == m_) {
      Level0Map map;
      map.target_of = target_of_;
      map.diso = sum * 2.0 / (static_cast<double>(m_) * (m_ - 1));
      out.push_back(std::move(map));
      return;
    }
    for (int t = 0; t < m_prime_; ++t) {
      if (used_[t]) continue;
      double added = 0;
      for (int i = 0; i < depth; ++i)
        added += std::abs(s_(depth, i) - t_(t, target_of_[i]));
      if (sum + added >= max_sum_) continue;
      target_of_[depth] = t;
      used_[t] = 1;
      extend(depth + 1, sum + added, out);
      used_[t] = 0;
    }
  }

  const Eigen::MatrixXd& s_;
  const Eigen::MatrixXd& t_;
  int m_, m_prime_;
  double max_sum_;
  std::vector<int> target_of_;
  std::vector<unsigned char> used_;
};

}  // namespace

std::vector<Level0Map> search_level0(const Eigen::MatrixXd& source_distances,
                                     const Eigen::MatrixXd& target_distances, double max_diso,
                                     int max_maps, int threads) {
  const int m = static_cast<int>(source_distances.rows());
  const int m_prime = static_cast<int>(target_distances.rows());
  if (m < 2 || m_prime < m) return {};
  // D_iso = sum over unordered pairs / (M(M-1)/2); compare sums to avoid divisions.
  const double max_sum = max_diso * m * (m - 1) / 2.0;
  std::vector<std::vector<Level0Map>> per_first(m_prime);
  parallel_for(m_prime, resolve_thread_count(threads), [&](int first, int) {
    Enumerator enumerator(source_distances, target_distances, max_sum);
    enumerator.run_from(first, per_first[first]);
  });
  std::vector<Level0Map> all;
  for (auto& part : per_first)
    for (auto& map : part) all.push_back(std::move(map));
  auto better = [](const Level0Map& a, const Level0Map& b) {
    return a.diso != b.diso ? a.diso < b.diso : a.target_of < b.target_of;
  };
  const size_t keep = std::min(all.size(), static_cast<size_t>(std::max(1, max_maps)));
  std::partial_sort(all.begin(), all.begin() + keep, all.end(), better);
  all.resize(keep);
  return all;
}

Level0Drop drop_level0_maps(std::vector<Level0Map>& maps, const std::vector<double>& disagreement,
                            double max_disagreement) {
  Level0Drop outcome;
  if (maps.empty()) return outcome;
  const size_t least = std::min_element(disagreement.begin(), disagreement.end()) - disagreement.begin();
  std::vector<Level0Map> kept;
  for (size_t i = 0; i < maps.size(); ++i)
    if (disagreement[i] <= max_disagreement) kept.push_back(std::move(maps[i]));
  if (kept.empty()) {
    kept.push_back(std::move(maps[least]));
    outcome.none_agreed = true;
  }
  outcome.dropped = static_cast<int>(maps.size() - kept.size());
  maps = std::move(kept);
  return outcome;
}

int jump_rule_count(const std::vector<Level0Map>& maps) {
  const int count = static_cast<int>(maps.size());
  if (count <= 1) return count;
  const int last = std::min(count, 11);  // D_1..D_11 (1-based), differences l = 2..11
  double mean_gap = 0;
  for (int l = 1; l < last; ++l) mean_gap += maps[l].diso - maps[l - 1].diso;
  mean_gap /= (last - 1);
  const double delta = 2.0 * mean_gap;
  for (int n = 1; n < count; ++n)
    if (maps[n].diso - maps[n - 1].diso > delta) return n;
  return count;
}

}  // namespace isocorr
