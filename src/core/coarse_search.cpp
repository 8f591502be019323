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
                                    const std::vector<Eigen::Isometry3d>& hypotheses, double radius,
                                    double yaw_step) {
  std::vector<CoarseHit> hits;
  if (columns.empty() || query.size == 0) return hits;
  const int steps = static_cast<int>(std::floor(radius / query.cell));
  std::vector<std::pair<int, int>> cells;
  cells.reserve(columns.size());
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
        cells.emplace_back(gridCell((m.x() + query.radius) / query.cell),
                           gridCell((m.y() + query.radius) / query.cell));
      }
      for (int dy = -steps; dy <= steps; ++dy) {
        for (int dx = -steps; dx <= steps; ++dx) {
          float sum = 0.0f;
          for (const auto& c : cells) {
            const int x = c.first + dx, y = c.second + dy;
            if (x >= 0 && y >= 0 && x < query.size && y < query.size) {
              sum += query.value[static_cast<std::size_t>(y) * query.size + x];
            }
          }
          // Ties go to the smaller offset (the prior is usually close).
          const double score = sum / columns.size() - 1e-6 * (std::abs(dx) + std::abs(dy) + std::abs(k));
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
