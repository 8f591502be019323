#include "scan_context_loop/core/coarse_search.h"

#include <algorithm>
#include <cmath>

#include "grid_cell.h"

namespace scan_context_loop {

StructureMap structureMap(const VoxelCloud& cloud, float cell) {
  StructureMap map;
  map.cell = cell;
  map.radius = cloud.max_range + cell;
  map.size = static_cast<int>(std::ceil(2.0f * map.radius / cell));
  map.value.assign(static_cast<std::size_t>(map.size) * map.size, 0.0f);
  std::vector<std::uint8_t> solid(map.value.size(), 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud.vertical(i)) continue;
    const int ix = gridCell((cloud.means[i].x() + map.radius) / cell);
    const int iy = gridCell((cloud.means[i].y() + map.radius) / cell);
    if (ix < 0 || iy < 0 || ix >= map.size || iy >= map.size) continue;
    solid[static_cast<std::size_t>(iy) * map.size + ix] = 1;
  }
  for (int iy = 0; iy < map.size; ++iy) {
    for (int ix = 0; ix < map.size; ++ix) {
      if (!solid[static_cast<std::size_t>(iy) * map.size + ix]) continue;
      ++map.columns;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = ix + dx, y = iy + dy;
          if (x < 0 || y < 0 || x >= map.size || y >= map.size) continue;
          float& v = map.value[static_cast<std::size_t>(y) * map.size + x];
          v = std::max(v, dx == 0 && dy == 0 ? 1.0f : 0.5f);
        }
      }
    }
  }
  return map;
}

std::vector<Eigen::Vector2f> structureColumns(const VoxelCloud& cloud, float cell) {
  std::vector<std::pair<int, int>> keys;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud.vertical(i)) continue;
    keys.emplace_back(gridCell(cloud.means[i].x() / cell), gridCell(cloud.means[i].y() / cell));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  // An even share of at most kMaxColumns: the score is a mean, and the search cost is linear in it.
  constexpr std::size_t kMaxColumns = 600;
  const double step = std::max(1.0, static_cast<double>(keys.size()) / kMaxColumns);
  std::vector<Eigen::Vector2f> columns;
  for (double i = 0; i < keys.size(); i += step) {
    const auto& k = keys[static_cast<std::size_t>(i)];
    columns.emplace_back((k.first + 0.5f) * cell, (k.second + 0.5f) * cell);
  }
  return columns;
}

std::vector<CoarseHit> coarseSearch(const StructureMap& query, const std::vector<Eigen::Vector2f>& columns,
                                    const std::vector<Eigen::Isometry3d>& hypotheses, double radius, double yaw_step) {
  std::vector<CoarseHit> hits;
  if (columns.empty() || query.size == 0) return hits;
  const int steps = static_cast<int>(std::floor(radius / query.cell));
  // The map framed by 2 * steps empty cells on every side: a column within `steps` of the map stays on
  // the framed map under every shift, so the sums need no bounds checks (a column farther out adds
  // nothing under any shift and is left out).
  const int pad = 2 * steps;
  const int width = query.size + 2 * pad;
  std::vector<float> framed(static_cast<std::size_t>(width) * width, 0.0f);
  for (int y = 0; y < query.size; ++y) {
    std::copy_n(query.value.begin() + static_cast<std::ptrdiff_t>(y) * query.size, query.size,
                framed.begin() + static_cast<std::ptrdiff_t>(y + pad) * width + pad);
  }
  std::vector<std::ptrdiff_t> cells;
  cells.reserve(columns.size());
  std::vector<float> sums(static_cast<std::size_t>(2 * steps + 1));
  for (std::size_t h = 0; h < hypotheses.size(); ++h) {
    const Eigen::Isometry3d& guess = hypotheses[h];
    const double yaw0 = std::atan2(guess(1, 0), guess(0, 0));
    CoarseHit best;
    best.hypothesis = static_cast<int>(h);
    best.score = -1.0;
    for (int k = -1; k <= 1; ++k) {
      const double yaw = yaw0 + k * yaw_step;
      const Eigen::Matrix2f R = Eigen::Rotation2Df(static_cast<float>(yaw)).toRotationMatrix();
      const Eigen::Vector2f t = guess.translation().head<2>().cast<float>();
      // Integer cells of the moved columns: every translation is then a shift of whole cells.
      cells.clear();
      for (const Eigen::Vector2f& c : columns) {
        const Eigen::Vector2f m = R * c + t;
        const int x = gridCell((m.x() + query.radius) / query.cell);
        const int y = gridCell((m.y() + query.radius) / query.cell);
        if (x < -steps || y < -steps || x >= query.size + steps || y >= query.size + steps) continue;
        cells.push_back(static_cast<std::ptrdiff_t>(y + pad) * width + (x + pad));
      }
      for (int dy = -steps; dy <= steps; ++dy) {
        // The sums of one row of shifts together: each column adds a run of 2 * steps + 1 neighbouring
        // cells, which vectorises. The map holds 0, 0.5 and 1 only, so every partial sum is exact in
        // float and the order of the additions cannot change a score.
        std::fill(sums.begin(), sums.end(), 0.0f);
        const std::ptrdiff_t row = static_cast<std::ptrdiff_t>(dy) * width - steps;
        for (const std::ptrdiff_t c : cells) {
          const float* run = framed.data() + (c + row);
          for (std::size_t j = 0; j < sums.size(); ++j) sums[j] += run[j];
        }
        for (int dx = -steps; dx <= steps; ++dx) {
          // Ties go to the smaller offset (the prior is usually close).
          const double score = sums[static_cast<std::size_t>(dx + steps)] / columns.size() -
                               1e-6 * (std::abs(dx) + std::abs(dy) + std::abs(k));
          if (score > best.score) {
            best.score = score;
            best.pose = Eigen::Isometry3d::Identity();
            best.pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
            best.pose.translation() << t.x() + dx * query.cell, t.y() + dy * query.cell, guess.translation().z();
          }
        }
      }
    }
    hits.push_back(best);
  }
  std::sort(hits.begin(), hits.end(), [](const CoarseHit& a, const CoarseHit& b) { return a.score > b.score; });
  return hits;
}

}  // namespace scan_context_loop
