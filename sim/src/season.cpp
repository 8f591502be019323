// Leaf-off (WorldOptions::season): broadleaved trees lose their leaves, hedges and bushes thin out.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "world_changes.h"

namespace scan_context_loop {
namespace sim {

namespace {

/// Every version of a plant: the one built and those that replaced it when it grew or was cut (the
/// changed world), found by where it stands, which those changes keep.
class Versions {
 public:
  explicit Versions(const StreetKit& kit) {
    for (std::size_t i = 0; i < kit.out.size(); ++i) {
      if (kit.out[i].material == Material::kFoliage) index_[key(kit.out[i])].push_back(i);
    }
  }
  const std::vector<std::size_t>& of(const Primitive& p) const {
    static const std::vector<std::size_t> none;
    const auto it = index_.find(key(p));
    return it == index_.end() ? none : it->second;
  }

 private:
  static std::uint64_t key(const Primitive& p) {
    std::uint32_t x, y;
    std::memcpy(&x, &p.center.x(), sizeof x);
    std::memcpy(&y, &p.center.y(), sizeof y);
    return mix(static_cast<std::uint64_t>(x) << 32 | y) ^ static_cast<std::uint64_t>(p.kind);
  }
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> index_;
};

/// From `when` on, each version of a plant (those present then or later) gives way to what `bare`
/// makes of it, for the rest of that version's time.
template <typename Bare>
void fromThenOn(StreetKit& kit, const std::vector<std::size_t>& versions, double when, Bare bare) {
  for (const std::size_t v : versions) {
    const Primitive before = kit.out[v];
    if (before.present_to <= when) continue;
    const double from = std::max(before.present_from, when);
    kit.out[v].present_to = from;
    for (Primitive after : bare(before)) {
      after.present_from = from;
      after.present_to = before.present_to;
      kit.out.push_back(after);
    }
  }
}

Primitive vertical(const Eigen::Vector2f& c, float radius, float z0, float z1) {
  Primitive p;
  p.kind = Primitive::Kind::kCylinder;
  p.material = Material::kBranch;
  p.center = Eigen::Vector3f(c.x(), c.y(), 0.0f);
  p.half = Eigen::Vector3f::Constant(radius);
  p.z0 = z0;
  p.z1 = z1;
  return p;
}

/// A broadleaved canopy in winter: the leader going on up from the trunk, 3-5 limbs spread through the
/// crown (5-12 cm thick: thinner than most beams' footprint beyond 30 m), and the twigs as a crown a
/// ray mostly passes (mean free path 8-14 m: a ray crossing 3 m of it returns a quarter of the time,
/// where the leaves returned nearly every one).
std::vector<Primitive> bareCrown(StreetKit& kit, const Primitive& canopy) {
  std::vector<Primitive> bare;
  const float r = canopy.half.x(), rz = canopy.half.z();
  const float bottom = canopy.center.z() - rz;
  const Eigen::Vector2f c(canopy.center.x(), canopy.center.y());
  bare.push_back(vertical(c, static_cast<float>(kit.uniform(0.05, 0.09)), bottom - 0.3f, bottom + 1.5f * rz));
  const int limbs = 3 + static_cast<int>(kit.uniform(0.0, 3.0));
  for (int i = 0; i < limbs; ++i) {
    const double angle = kit.uniform(0.0, 2.0 * M_PI), reach = kit.uniform(0.3, 0.65) * r;
    const Eigen::Vector2f at = c + Eigen::Vector2f(static_cast<float>(reach * std::cos(angle)),
                                                   static_cast<float>(reach * std::sin(angle)));
    bare.push_back(vertical(at, static_cast<float>(kit.uniform(0.025, 0.06)), bottom + 0.2f * rz,
                            bottom + static_cast<float>(kit.uniform(1.2, 1.8)) * rz));
  }
  Primitive twigs = canopy;
  twigs.material = Material::kBranch;
  twigs.half *= 0.9f;
  twigs.free_path = static_cast<float>(kit.uniform(8.0, 14.0));
  bare.push_back(twigs);
  return bare;
}

}  // namespace

void leafOff(const StreetRecord& record, const Changes& c, StreetKit* kit) {
  const Versions versions(*kit);
  for (const StreetRecord::Tree& tree : record.trees) {
    if (tree.conifer || !kit->chance(c.strength)) continue;
    const double when = changeTime(*kit, c);
    const Primitive canopy = kit->out[tree.canopy];
    fromThenOn(*kit, versions.of(canopy), when, [&](const Primitive& p) { return bareCrown(*kit, p); });
  }
  // Hedges and bushes stay, thinner: light passes three to four times as far into them.
  const auto thin = [&](const std::vector<std::size_t>& plants) {
    for (const std::size_t plant : plants) {
      if (!kit->chance(c.strength)) continue;
      const double when = changeTime(*kit, c);
      const float factor = static_cast<float>(kit->uniform(3.0, 4.0));
      const Primitive built = kit->out[plant];
      fromThenOn(*kit, versions.of(built), when, [&](Primitive p) {
        p.free_path *= factor;
        return std::vector<Primitive>{p};
      });
    }
  };
  thin(record.hedges);
  thin(record.bushes);
}

}  // namespace sim
}  // namespace scan_context_loop
