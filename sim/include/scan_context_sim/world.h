// A procedural street world for simulating LiDAR scans: ground and raised pavements, buildings, front
// hedges, walls and fences, parked cars (some of which come, go or move between visits), trees, street
// lights, signs and bushes, placed along a driven path; and ray casting through it.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace scan_context_loop {
namespace sim {

enum class Material : std::uint8_t {
  kGround,    ///< asphalt
  kPavement,  ///< raised concrete pavement between the kerb and the property line
  kBuilding,
  kWall,  ///< walls and fences
  kCar,
  kTrunk,
  kFoliage,  ///< tree canopies, hedges, bushes
  kPole,     ///< street lights and their arms
  kSign,     ///< retro-reflective sign boards
  kPerson,   ///< pedestrians
  /// Bare branches of a leaf-off tree (WorldOptions::season): limbs thinner than a beam's footprint
  /// and the twigs of the crown. Thin limbs return as much of a beam as they cover (SensorModel).
  kBranch,
  kContainer  ///< shipping containers (painted steel)
};

/// One solid. Boxes are vertical prisms with a yaw; cylinders are vertical; ellipsoids are axis-aligned.
struct Primitive {
  enum class Kind : std::uint8_t { kBox, kCylinder, kEllipsoid } kind = Kind::kBox;
  Material material = Material::kBuilding;
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  ///< box/cylinder: z is unused (see z0, z1)
  Eigen::Vector3f half = Eigen::Vector3f::Ones();    ///< half extents (box), radius in x (cylinder), radii (ellipsoid)
  float yaw = 0.0f;                                  ///< box only
  float z0 = 0.0f, z1 = 1.0f;                        ///< box and cylinder vertical extent
  /// Porous solids (foliage, hedges, wire fences; boxes and ellipsoids): the mean distance a ray travels
  /// inside before something returns it [m], so canopies scatter returns through their depth and
  /// let some rays through. 0: opaque.
  float free_path = 0.0f;
  /// Present only for times in [present_from, present_to) (seconds); always present by default.
  double present_from = -1e300, present_to = 1e300;
};

struct Hit {
  float range = 0.0f;
  /// Width of a thin solid across the ray (a cylinder's diameter) [m]; 0 for the others.
  float width = 0.0f;
  Material material = Material::kGround;
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();
};

/// Ground plane z = slope_x * x + slope_y * y + offset, and the solids, with a 2D grid for ray casting.
class World {
 public:
  World() = default;
  World(std::vector<Primitive> primitives, const Eigen::Vector3d& ground, float cell_size = 4.0f);

  /// Height of the ground at (x, y).
  double groundZ(double x, double y) const { return ground_.x() * x + ground_.y() * y + ground_.z(); }

  /// First surface along origin + t * direction (direction unit length) within max_range, at `time`.
  /// `visit` must hold one int per primitive, all different from `ray_id` before the first call
  /// (mailboxing: each solid is tested once per ray); callers give each thread its own.
  bool cast(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float max_range, double time,
            std::uint32_t ray_id, std::vector<std::uint32_t>* visit, Hit* hit) const;

  const std::vector<Primitive>& primitives() const { return primitives_; }
  std::size_t size() const { return primitives_.size(); }

 private:
  std::vector<Primitive> primitives_;
  std::vector<Eigen::Vector2f> yaw_axes_;             // cos and sin of each box's yaw, so rays need no trigonometry
  Eigen::Vector3d ground_ = Eigen::Vector3d::Zero();  // slope_x, slope_y, offset
  float cell_ = 4.0f;
  float min_x_ = 0.0f, min_y_ = 0.0f;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<std::uint32_t>> cells_;
};

/// Nearest return of the ray origin + t * direction from one solid, for t in (0, t_max]. A ray starting
/// inside a solid sees nothing of it (the sensor is never inside one). For a porous solid, `scatter` in
/// [0, 1) picks how deep the ray gets: it returns from -free_path * ln(1 - scatter) past the surface,
/// or passes through when that is beyond the far side.
bool intersect(const Primitive& p, const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_max,
               float scatter, Hit* hit);

/// A pose along the driven path, for placing the street around it.
struct PathPoint {
  double x, y, heading;
};

struct WorldOptions {
  std::uint32_t seed = 1;
  double road_half_width = 6.0;       ///< path (road centre) to kerb [m]: a lane and a parking lane
  double ground_slope = 0.01;         ///< gentle slope of the ground plane (rise per metre)
  double dynamic_car_fraction = 0.3;  ///< parked cars that leave, arrive or move during the drive
  double duration = 0.0;              ///< length of the drive [s]; 0: every car stays put
  double district_size = 160.0;       ///< side of the squares that share a street character [m]
  /// How much the world changes during the drive, as between visits days apart (0: not at all; 1: a
  /// strong change): parked cars leave, arrive or move, trees and hedges grow or are cut, construction
  /// sites appear, and traffic and pedestrians pass. Each change happens at its own time in the drive,
  /// so places seen further apart in time differ more. Needs a duration.
  double changed_world = 0.0;
  /// Traffic and pedestrians of changed_world, as a multiple of its own (1): 3 is a busy street at rush
  /// hour (about 3 vehicles every 4 s at strength 1). Applies to a later drive's passing traffic too.
  double traffic = 1.0;
  /// Buildings and their frontage from a few designs per district character, one per district square
  /// (rows of identical houses), so different streets look alike (repetitive places).
  bool repeat_templates = false;
  /// Cars park at the kerb and (with changed_world) drive along the path. Off for footpaths, campus
  /// paths and alleys, where road_half_width is small (2.5-3 m): no parked cars, no traffic.
  bool vehicles = true;
  /// Drive time at each path point [s], so traffic keeps clear of the sensor; empty: the path driven at
  /// a uniform speed over `duration`.
  std::vector<double> times;
  // Harder changes (0: off, the world as without them; 1: strong). Each is drawn from a generator of
  // its own, keyed by the seed, so switching one on leaves every other solid and change as it was. Each
  // change happens at its own time in the drive, as changed_world's do; all need a duration.
  /// Leaf-off season: about `season` of the broadleaved trees lose their leaves (trunk, a few limbs
  /// and a sparse crown of twigs stay), and as many hedges and bushes thin out.
  double season = 0.0;
  /// Building sites: about `construction` per 100 m of drive of site fences (mesh panels along the
  /// pavement or round a lot) and stacks of shipping containers at the kerb or in lots.
  double construction = 0.0;
  /// About `furniture` of the benches, bins, cabinets, bollard rows, sign posts and bus shelters are
  /// moved along the pavement or taken away, and new ones appear.
  double furniture = 0.0;
  /// A different density on each pass: the drive's clock is cut into passes (at stops over a minute,
  /// and every pass_seconds), and each pass draws its own share of parked cars present, of empty spaces
  /// taken and a traffic multiplier, spread wider the larger this is (1: 30-100 % of the parked cars,
  /// traffic x1/3 to x3). With it, the traffic of changed_world is drawn per pass.
  double pass_traffic = 0.0;
  double pass_seconds = 180.0;
  /// The kind of place the streets are built as: the city's districts (terraces, houses, avenues,
  /// industrial estates), or a suburb of detached houses on plots behind front gardens and fences, with
  /// garages, cars on driveways, side fences between the plots and trees on grass verges.
  enum class Style : std::uint8_t { kCity, kSuburb } style = Style::kCity;
};

/// Builds streets along the path. Each district-sized square of the map gets a character -- terraced
/// blocks, detached houses with front gardens, a tree-lined avenue or an industrial estate -- that sets
/// the building sizes, heights, setbacks and gaps, the front hedges, walls and fences, the street trees
/// and how densely cars park. Nothing is ever placed on a road (within reach of any path point), so any
/// path, including one that crosses or revisits itself, gets open streets.
World generateWorld(const std::vector<PathPoint>& path, const WorldOptions& options);

/// The streets along several paths at once (a team's drives, teamStreets()), each walked on its own
/// (no road joins one path's end to the next one's start), nothing placed on any of them. The changed
/// world is left out (changed_world must be 0: its traffic follows one drive's clock).
World generateWorld(const std::vector<std::vector<PathPoint>>& paths, const WorldOptions& options);

/// A later drive through the world that generateWorld(path, options) builds, on another day: the same
/// streets, buildings and everything else built, as the first drive left them, with the street
/// changed since (WorldOptions::changed_world's changes at strength `changed`, all made by the later
/// drive's start, on things that had not changed yet), and traffic and people passing the later drive.
struct LaterDrive {
  std::vector<PathPoint> path;  ///< within the streets built along the first drive's path
  std::vector<double> times;    ///< the world's clock at each path point [s], after the first drive's end
  double changed = 1.0;         ///< 0 to 1
};

/// That world: generateWorld(path, options) has the same solids at the first drive's times.
World generateWorld(const std::vector<PathPoint>& path, const WorldOptions& options, const LaterDrive& later);

}  // namespace sim
}  // namespace scan_context_loop
