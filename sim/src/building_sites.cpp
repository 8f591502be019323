// Building sites of the harder changed world (WorldOptions::construction): site fences and shipping
// containers, which stand for weeks and change a street's outline more than a skip does.
#include <algorithm>
#include <cmath>

#include "world_changes.h"

namespace scan_context_loop {
namespace sim {

namespace {

constexpr double kContainerWidth = 2.44, kContainerHeight = 2.59;  // ISO containers
constexpr double kPanel = 3.5;                                     // a mesh fence panel's length

/// The solids of one site, placed together once their footprint is free.
struct Site {
  Footprint footprint;
  std::vector<Primitive> solids;
};

bool placeSite(StreetKit& kit, const Site& site, double clearance, double margin, double when) {
  if (!kit.roads.clear(site.footprint, clearance) || !kit.occupied.free(site.footprint, margin)) return false;
  kit.occupied.mark(site.footprint);
  for (Primitive p : site.solids) {
    p.present_from = when;
    kit.out.push_back(p);
  }
  return true;
}

/// A run of mesh fence panels (2 m tall, porous: the mesh returns about half the rays) from `a` to `b`.
void meshFence(StreetKit& kit, const Eigen::Vector2d& a, const Eigen::Vector2d& b, std::vector<Primitive>* out) {
  const Eigen::Vector2d d = b - a;
  const double length = d.norm(), yaw = std::atan2(d.y(), d.x());
  const int panels = std::max(1, static_cast<int>(std::lround(length / kPanel)));
  for (int i = 0; i < panels; ++i) {
    const Eigen::Vector2d c = a + d * ((i + 0.5) / panels);
    Primitive panel = kit.box(c, yaw, length / panels / 2 - 0.03, 0.03, 0.0, 2.0, Material::kWall);
    panel.free_path = 0.08f;
    out->push_back(panel);
  }
}

/// Containers `columns` side by side across, `tiers` high, each `length` long, centred at c with the
/// street's heading; the upper ones a little off the ones below, as they are set down.
void containerStack(StreetKit& kit, const Eigen::Vector2d& c, double heading, double length, int columns, int tiers,
                    std::vector<Primitive>* out) {
  const Eigen::Vector2d across(-std::sin(heading), std::cos(heading)), along(std::cos(heading), std::sin(heading));
  for (int col = 0; col < columns; ++col) {
    const double offset = (col - (columns - 1) / 2.0) * (kContainerWidth + 0.15);
    for (int tier = 0; tier < tiers; ++tier) {
      const Eigen::Vector2d at = c + offset * across + kit.uniform(-0.25, 0.25) * along;
      out->push_back(kit.box(at, heading + kit.uniform(-0.01, 0.01), length / 2, kContainerWidth / 2,
                             tier * kContainerHeight, (tier + 1) * kContainerHeight, Material::kContainer));
    }
  }
}

}  // namespace

void addBuildingSites(const Changes& c, StreetKit* kit_ptr) {
  StreetKit& kit = *kit_ptr;
  placeSeveral(
      c.strength * static_cast<double>(kit.dense.size()) / 100.0,
      [&] {
        const PathPoint& p = randomPlace(kit);
        const double sign = kit.chance(0.5) ? 1.0 : -1.0;
        const Style& style = styleOf(kit.districtAt(StreetKit::at(p, 0.0, sign * 15.0)));
        const double line = kit.propertyLine(style);
        const double when = changeTime(kit, c);
        const double kind = kit.uniform(0.0, 1.0);
        Site site;
        if (kind < 0.35) {  // a site fence along the pavement, 10-35 m
          const double length = kit.uniform(10.0, 35.0);
          const double lateral = kit.kerb() + 0.4 + kit.uniform(0.0, std::max(0.0, style.pavement - 0.8));
          meshFence(kit, StreetKit::at(p, 0.0, sign * lateral), StreetKit::at(p, length, sign * lateral), &site.solids);
          site.footprint = StreetKit::footprintOf(StreetKit::at(p, length / 2, sign * lateral), p.heading, length / 2, 0.1);
          return placeSite(kit, site, kit.kerb() + 0.1, 0.1, when);
        }
        if (kind < 0.6) {  // a fenced lot behind the property line, a site cabin or containers in it
          const double length = kit.uniform(12.0, 30.0), depth = kit.uniform(8.0, 16.0);
          const double near = line + 0.3, far = near + depth;
          const Eigen::Vector2d corners[4] = {StreetKit::at(p, 0.0, sign * near), StreetKit::at(p, length, sign * near),
                                              StreetKit::at(p, length, sign * far), StreetKit::at(p, 0.0, sign * far)};
          for (int k = 0; k < 4; ++k) meshFence(kit, corners[k], corners[(k + 1) % 4], &site.solids);
          const Eigen::Vector2d inside = StreetKit::at(p, length / 2, sign * (near + depth / 2));
          if (kit.chance(0.5)) {
            site.solids.push_back(kit.box(inside, p.heading, 3.0, 1.2, 0.0, kit.uniform(2.5, 2.8), Material::kContainer));
          } else {
            containerStack(kit, inside, p.heading, 6.06, 1 + static_cast<int>(kit.uniform(0.0, 2.0)),
                           1 + static_cast<int>(kit.uniform(0.0, 2.0)), &site.solids);
          }
          site.footprint = StreetKit::footprintOf(StreetKit::at(p, length / 2, sign * (near + depth / 2)), p.heading,
                                                  length / 2, depth / 2);
          return placeSite(kit, site, line - 0.3, 0.2, when);
        }
        // A stack of containers: one 20 ft at the kerb, or 1-3 across and 1-3 high in a lot.
        // At the kerb only where vehicles park (not along footpaths).
        const bool kerbside = kit.chance(0.4) && kit.options.vehicles;
        const double length = kerbside || kit.chance(0.5) ? 6.06 : 12.19;
        const int columns = kerbside ? 1 : 1 + static_cast<int>(kit.uniform(0.0, 3.0));
        const int tiers = kerbside ? 1 : 1 + static_cast<int>(kit.uniform(0.0, 3.0));
        const double half_across = columns * (kContainerWidth + 0.15) / 2;
        const double lateral = kerbside ? kit.kerb() - 0.2 - kContainerWidth / 2 : line + 1.0 + half_across;
        const Eigen::Vector2d centre = StreetKit::at(p, length / 2, sign * lateral);
        containerStack(kit, centre, p.heading, length, columns, tiers, &site.solids);
        site.footprint = StreetKit::footprintOf(centre, p.heading, length / 2 + 0.3, kerbside ? kContainerWidth / 2 : half_across);
        // A container is wider than a car: at the kerb it takes half a metre more of the lane.
        return placeSite(kit, site, kerbside ? kit.parkingClearance() - 0.5 : line - 0.3, 0.3, when);
      },
      8);
}

}  // namespace sim
}  // namespace scan_context_loop
