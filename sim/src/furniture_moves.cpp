// Street furniture that is moved or taken away between visits (WorldOptions::furniture).
#include <cmath>

#include "world_changes.h"

namespace scan_context_loop {
namespace sim {

namespace {

/// The ground footprint of a solid (a cylinder as its square).
Footprint footprintOf(const Primitive& p) {
  if (p.kind == Primitive::Kind::kBox) return StreetKit::footprintOf(p);
  return StreetKit::footprintOf(Eigen::Vector2d(p.center.x(), p.center.y()), 0.0, p.half.x(), p.half.x());
}

/// The piece moved by `offset`, when every solid of it lands on free pavement; marks where it went.
bool moveTo(StreetKit& kit, const StreetRecord::Furniture& piece, const Eigen::Vector2d& offset, double when) {
  std::vector<Primitive> moved;
  for (const std::size_t i : piece.solids) {
    Primitive p = kit.out[i];
    p.center.x() += static_cast<float>(offset.x());
    p.center.y() += static_cast<float>(offset.y());
    // Each solid needs free pavement where it lands; the piece's own old place is still marked, which a
    // move of 2 m or more clears.
    const Footprint f = footprintOf(p);
    if (!kit.roads.clear(f, kit.kerb() + 0.1) || !kit.occupied.free(f, 0.1)) return false;
    moved.push_back(p);
  }
  for (std::size_t k = 0; k < moved.size(); ++k) {
    kit.occupied.mark(footprintOf(moved[k]));
    replaceAt(kit, piece.solids[k], moved[k], when);
  }
  return true;
}

}  // namespace

void moveFurniture(const StreetRecord& record, const Changes& c, StreetKit* kit_ptr) {
  StreetKit& kit = *kit_ptr;
  for (const StreetRecord::Furniture& piece : record.furniture) {
    if (!kit.chance(c.strength)) continue;
    const double when = changeTime(kit, c);
    const bool taken = kit.chance(1.0 / 3.0);
    const double along = kit.eitherWay(2.0, 12.0), across = kit.uniform(-0.3, 0.3);
    const Eigen::Vector2d offset = along * Eigen::Vector2d(std::cos(piece.heading), std::sin(piece.heading)) +
                                   across * Eigen::Vector2d(-std::sin(piece.heading), std::cos(piece.heading));
    if (taken || !moveTo(kit, piece, offset, when)) {
      for (const std::size_t i : piece.solids) removeAt(kit, i, when);
    }
  }
  // New benches and bins: about one per 60 m of drive at full strength.
  placeSeveral(c.strength * static_cast<double>(kit.dense.size()) / 60.0, [&] {
    const PathPoint& p = randomPlace(kit);
    const double sign = kit.chance(0.5) ? 1.0 : -1.0;
    const Style& style = styleOf(kit.districtAt(StreetKit::at(p, 0.0, sign * 15.0)));
    const bool bench = kit.chance(0.5);
    const double lateral = bench ? kit.propertyLine(style) - 0.4 : kit.kerb() + 0.6;
    Primitive piece = kit.box(StreetKit::at(p, 0.0, sign * lateral), p.heading, bench ? 0.9 : 0.3, 0.3, 0.0,
                              bench ? kit.uniform(0.45, 0.8) : kit.uniform(0.9, 1.2), Material::kWall);
    piece.present_from = changeTime(kit, c);
    return kit.placeBox(piece, kit.kerb() + 0.1, 0.2);
  });
}

}  // namespace sim
}  // namespace scan_context_loop
