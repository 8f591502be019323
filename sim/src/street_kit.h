// What the street generator and the changes between visits share: the district characters, the
// random draws, and making solids where there is room for them. Internal to the simulator library.
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "placement.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

enum class District : std::uint8_t { kTerrace, kHouses, kAvenue, kIndustrial };

/// What a street looks like in one kind of district. Lengths in metres, chances in [0, 1].
struct Style {
  double pavement;                  ///< kerb to property line
  double frontage;                  ///< chance a stretch of property line has a hedge, wall or fence
  double setback_min, setback_max;  ///< property line to facade
  double length_min, length_max;    ///< facade length
  double depth_min, depth_max;
  double height_min, height_max;
  double tower;               ///< chance of a building 20-30 m tall
  double adjoining;           ///< chance the next building shares a wall with this one
  double gap_min, gap_max;    ///< otherwise the gap between buildings
  double open_lot;            ///< chance of a longer opening: a yard, car park or side lane
  double back_row;            ///< chance of a second building behind the first
  double street_tree;         ///< chance each tree pit holds a tree
  double tree_min, tree_max;  ///< tree pit spacing
  double parking;             ///< chance a parking space holds a car
  double garden;              ///< chance of trees and bushes in a front garden
  bool industrial;            ///< wire-mesh fences, lorries among the parked vehicles
};

const Style& styleOf(District d);

/// A 64-bit mixing function (splitmix64's finaliser), for repeatable draws keyed by numbers.
std::uint64_t mix(std::uint64_t z);

/// The ground plane (slope_x, slope_y, offset): the configured slope, downhill in a direction drawn
/// from the seed.
Eigen::Vector3d groundPlane(const WorldOptions& options);

/// Sizes of one vehicle: body, and a narrower cabin on it (cabin_frac of the length; 0: none).
struct VehicleShape {
  double length, width, body_top, roof, cabin_frac;
};

struct Vehicle {
  Primitive body, cabin;
  double length, width;
};

/// Indices into the solids of the things that can change between visits, and the parking spaces the
/// builder left empty, as the street builder leaves them.
struct StreetRecord {
  struct Car {
    std::size_t body, cabin;  ///< cabin == body when the vehicle is one block
  };
  struct Tree {
    std::size_t trunk, canopy;
    bool conifer;  ///< keeps its needles in winter
  };
  /// A piece of street furniture: its solids (a bench; a post and its sign; a row of bollards; a
  /// shelter's roof and back panel) and the street's heading where it stands.
  struct Furniture {
    std::vector<std::size_t> solids;
    double heading;
  };
  struct Space {
    PathPoint p;
    double sign;
    bool industrial;
  };
  std::vector<Car> parked;  ///< cars that stay for the whole drive
  std::vector<Space> empty_spaces;
  std::vector<Tree> trees;
  std::vector<std::size_t> bushes, hedges;
  std::vector<Furniture> furniture;
};

/// The solids placed so far, the roads and the room left, and the random draws. Every draw comes from
/// `rng`, which the world changes and the repeated templates point at generators of their own, so the
/// base world stays the same draw for draw whatever they do.
class StreetKit {
 public:
  StreetKit(const std::vector<PathPoint>& dense, const WorldOptions& options);

  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(*rng); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  /// A magnitude in [a, b), forwards or backwards (the sign drawn first).
  double eitherWay(double a, double b) {
    const double sign = chance(0.5) ? 1.0 : -1.0;
    return sign * uniform(a, b);
  }
  double kerb() const { return options.road_half_width; }
  /// Nothing stands, hangs or reaches within this of a path point [m]. With the default kerb (6 m)
  /// nothing comes near it anyway; on a narrow path (road_half_width 2.5-3 m) it keeps lamp arms,
  /// canopies and things in the parking lane out of the sensor's way.
  static constexpr double kPathClearance = 1.5;
  double propertyLine(const Style& style) const { return kerb() + style.pavement; }

  /// A repeatable draw for the district-sized square of the map that q lies in.
  std::uint64_t squareDraw(const Eigen::Vector2d& q) const;
  /// The district a point lies in, from its square's draw.
  District districtAt(const Eigen::Vector2d& q) const;
  /// Point at along-track offset `along` and lateral offset `lateral` (positive = left) from p.
  static Eigen::Vector2d at(const PathPoint& p, double along, double lateral);
  double groundAt(const Eigen::Vector2d& c) const { return ground.x() * c.x() + ground.y() * c.y() + ground.z(); }

  static Footprint footprintOf(const Eigen::Vector2d& c, double yaw, double hx, double hy);
  /// The footprint of a box.
  static Footprint footprintOf(const Primitive& b);
  Primitive box(const Eigen::Vector2d& c, double yaw, double hx, double hy, double z0, double z1, Material m) const;
  Primitive cylinder(const Eigen::Vector2d& c, double radius, double z0, double z1, Material m) const;
  Primitive ellipsoid(const Eigen::Vector2d& c, double z, const Eigen::Vector3d& radii, Material m,
                      double free_path) const;

  /// A hedge, wall or fence `length` long starting at p, just behind the property line.
  Primitive alongPropertyLine(const PathPoint& p, double sign, const Style& style, double length, double thickness,
                              double height, Material material) const {
    const Eigen::Vector2d c = at(p, length / 2, sign * (propertyLine(style) + 0.1 + thickness / 2));
    return box(c, p.heading, length / 2, thickness / 2, 0.0, height, material);
  }

  /// Adds the solid when its footprint keeps `clearance` from every road and, grown by `margin`,
  /// overlaps nothing placed; marks it as taken.
  bool place(const Primitive& prim, const Footprint& f, double clearance, double margin);
  bool placeBox(const Primitive& b, double clearance, double margin) {
    return place(b, footprintOf(b), clearance, margin);
  }

  /// A vehicle's sizes: a small car, a saloon or estate, an SUV or van, or (industrial) a box van or lorry.
  VehicleShape vehicleShape(bool industrial);
  /// That vehicle's body and cabin, its rear `along` ahead of p and its centre `lateral` to the side.
  Vehicle vehicleAt(const VehicleShape& shape, const PathPoint& p, double along, double lateral, double yaw) const;
  /// A vehicle parked at the kerb on the `sign` side, its rear `along` ahead of p.
  Vehicle parkedVehicle(const PathPoint& p, double sign, double along, bool industrial);
  /// Adds body and cabin (the cabin only when it stands out of the body); returns where they went.
  StreetRecord::Car add(const Vehicle& v);
  /// Where parked vehicles may stand: at the road's edge, clear of other roads.
  double parkingClearance() const { return std::max(kerb() - 2.3, kPathClearance); }
  /// A trunk and a canopy (broad, or narrow and tall for a conifer) at c, `clearance` from every road;
  /// `scale` shrinks garden trees. Records the tree when it was placed.
  void tree(const Eigen::Vector2d& c, double clearance, double scale, StreetRecord* record);

  const std::vector<PathPoint>& dense;
  const WorldOptions& options;
  const Eigen::Vector3d ground;
  RoadMap roads;
  Occupancy occupied;
  std::vector<Primitive> out;
  std::mt19937 base_rng;
  std::mt19937* rng = &base_rng;
};

/// Points the kit's draws at another generator for as long as it lives.
class DrawFrom {
 public:
  DrawFrom(StreetKit& kit, std::mt19937* rng) : kit_(kit), saved_(kit.rng) { kit.rng = rng; }
  ~DrawFrom() { kit_.rng = saved_; }
  DrawFrom(const DrawFrom&) = delete;
  DrawFrom& operator=(const DrawFrom&) = delete;

 private:
  StreetKit& kit_;
  std::mt19937* saved_;
};

}  // namespace sim
}  // namespace scan_context_loop
