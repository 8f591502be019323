#include "scan_context_loop/core/database_file.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <utility>

#include <lz4.h>

#include "scan_context_loop/core/block_arena.h"
#include "scan_context_loop/core/byte_stream.h"
#include "scan_context_loop/core/crc32.h"
#include "scan_context_loop/core/file_io.h"
#include "scan_context_loop/core/registration.h"

namespace scan_context_loop {

namespace {

constexpr char kMagic[5] = {'S', 'C', 'L', 'D', 'B'};
constexpr std::uint32_t kFlagClouds = 1u;
/// magic, version, flags, num_rings, num_sectors, max_radius, min_range, lidar_height, ring_key,
/// gravity alignment, verify_voxel_leaf, verify_max_range, keyframes, sessions, payload bytes, payload CRC,
/// header CRC (over every header byte before it).
constexpr std::size_t kHeaderBytes = 5 + 4 + 4 + 4 + 4 + 8 + 8 + 8 + 1 + 1 + 8 + 8 + 8 + 4 + 8 + 4 + 4;
/// Pose: rows 0-2 of the 4x4 matrix, row-major (row 3 is 0 0 0 1).
constexpr int kPoseRows = 3;
/// A keyframe record's pose flag: no pose, the odometry's, or a backend's corrected pose.
constexpr std::uint8_t kNoPose = 0, kOdometryPose = 1, kCorrectedPose = 2;
/// A voxel in the compressed registration data: its mean (3 x f32), then, after all means, its normal
/// and shape (4 x i8).
constexpr std::size_t kVoxelBytes = 3 * sizeof(float) + 4;
static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "voxel means are read and written as float triples");
static_assert(sizeof(std::array<std::int8_t, 4>) == 4, "voxel normals are read and written as 4 bytes");
/// The payload is written, and skipped over for its checksum, in pieces of about this size.
constexpr std::size_t kChunkBytes = std::size_t(4) << 20;

// The file's codes for the enums, fixed whatever order the enums take.
constexpr RingKeyType kRingKeyCodes[] = {RingKeyType::kMeanHeight, RingKeyType::kOccupancy};
constexpr GravityAlignmentMode kGravityAlignmentCodes[] = {GravityAlignmentMode::kAuto, GravityAlignmentMode::kPose,
                                                           GravityAlignmentMode::kGround, GravityAlignmentMode::kOff};

template <typename E, std::size_t N>
std::uint8_t codeOf(E value, const E (&codes)[N]) {
  return static_cast<std::uint8_t>(std::find(codes, codes + N, value) - codes);
}

template <typename E, std::size_t N>
bool fromCode(std::uint8_t code, const E (&codes)[N], E* value) {
  if (code >= N) return false;
  *value = codes[code];
  return true;
}

/// What a file must share with the configuration that loads it.
struct FileSettings {
  std::uint32_t num_rings = 0, num_sectors = 0;
  double max_radius = 0.0, min_range = 0.0, lidar_height = 0.0;
  RingKeyType ring_key = RingKeyType::kMeanHeight;
  GravityAlignmentMode gravity_alignment = GravityAlignmentMode::kAuto;
  /// Registration data included: their voxel settings (both 0 without).
  bool clouds = false;
  double voxel_leaf = 0.0, voxel_max_range = 0.0;
};

struct Header {
  FileSettings settings;
  std::uint64_t keyframes = 0;
  std::uint32_t sessions = 0;
  std::uint64_t payload_bytes = 0;
  std::uint32_t payload_crc = 0;
};

FileSettings settingsOf(const Config& config, bool clouds) {
  FileSettings s;
  s.num_rings = static_cast<std::uint32_t>(config.num_rings);
  s.num_sectors = static_cast<std::uint32_t>(config.num_sectors);
  s.max_radius = config.max_radius;
  s.min_range = config.min_range;
  s.lidar_height = config.lidar_height;
  s.ring_key = config.ring_key;
  s.gravity_alignment = config.gravity_alignment;
  s.clouds = clouds;
  if (clouds) {
    s.voxel_leaf = config.verification.voxel_leaf;
    s.voxel_max_range = config.verification.max_range;
  }
  return s;
}

template <typename T>
std::string text(const T& value) {
  std::ostringstream out;
  out.precision(17);  // every double prints distinctly
  out << value;
  return out.str();
}

/// The pairs settingsMismatch compares, in its order: name, the file's value, the configuration's.
std::vector<std::array<std::string, 3>> settingRows(const FileSettings& file, const FileSettings& ours) {
  std::vector<std::array<std::string, 3>> rows = {
      {"num_rings", text(file.num_rings), text(ours.num_rings)},
      {"num_sectors", text(file.num_sectors), text(ours.num_sectors)},
      {"max_radius", text(file.max_radius), text(ours.max_radius)},
      {"min_range", text(file.min_range), text(ours.min_range)},
      {"lidar_height", text(file.lidar_height), text(ours.lidar_height)},
      {"ring_key", ringKeyTypeName(file.ring_key), ringKeyTypeName(ours.ring_key)},
      {"gravity_alignment", gravityAlignmentModeName(file.gravity_alignment),
       gravityAlignmentModeName(ours.gravity_alignment)},
  };
  if (file.clouds) {
    rows.push_back({"verify_voxel_leaf", text(file.voxel_leaf), text(ours.voxel_leaf)});
    rows.push_back({"verify_max_range", text(file.voxel_max_range), text(ours.voxel_max_range)});
  }
  return rows;
}

/// The first setting in which the file differs from the configuration, named by its configuration key
/// with both values; empty when they agree.
std::string settingsMismatch(const FileSettings& file, const FileSettings& ours) {
  const std::vector<std::array<std::string, 3>> rows = settingRows(file, ours);
  for (const auto& [name, saved, current] : rows) {
    if (saved != current) {
      return "saved with " + name + " " + saved + ", but the configuration has " + current +
             ": the saved keyframes cannot be compared with this configuration's";
    }
  }
  return "";
}

std::vector<std::uint8_t> encodeHeader(const Header& h) {
  ByteWriter out;
  out.bytes(kMagic, sizeof(kMagic));
  out.u32(kDatabaseFileVersion);
  out.u32(h.settings.clouds ? kFlagClouds : 0u);
  out.u32(h.settings.num_rings);
  out.u32(h.settings.num_sectors);
  out.f64(h.settings.max_radius);
  out.f64(h.settings.min_range);
  out.f64(h.settings.lidar_height);
  out.u8(codeOf(h.settings.ring_key, kRingKeyCodes));
  out.u8(codeOf(h.settings.gravity_alignment, kGravityAlignmentCodes));
  out.f64(h.settings.voxel_leaf);
  out.f64(h.settings.voxel_max_range);
  out.u64(h.keyframes);
  out.u32(h.sessions);
  out.u64(h.payload_bytes);
  out.u32(h.payload_crc);
  out.u32(crc32(out.buffer().data(), out.size()));
  return out.buffer();
}

/// Decodes the header fields after magic and version (whose checksum the caller checked).
std::string decodeHeader(ByteReader* in, Header* h) {
  std::uint32_t flags = 0;
  std::uint8_t ring_key = 0, gravity_alignment = 0;
  in->u32(&flags);
  in->u32(&h->settings.num_rings);
  in->u32(&h->settings.num_sectors);
  in->f64(&h->settings.max_radius);
  in->f64(&h->settings.min_range);
  in->f64(&h->settings.lidar_height);
  in->u8(&ring_key);
  in->u8(&gravity_alignment);
  in->f64(&h->settings.voxel_leaf);
  in->f64(&h->settings.voxel_max_range);
  in->u64(&h->keyframes);
  in->u32(&h->sessions);
  in->u64(&h->payload_bytes);
  in->u32(&h->payload_crc);
  in->take(4);  // the header checksum
  if ((flags & ~kFlagClouds) != 0) return "unknown flags " + text(flags) + " in the header";
  h->settings.clouds = (flags & kFlagClouds) != 0;
  if (!fromCode(ring_key, kRingKeyCodes, &h->settings.ring_key)) return "unknown ring_key code " + text(int(ring_key));
  if (!fromCode(gravity_alignment, kGravityAlignmentCodes, &h->settings.gravity_alignment)) {
    return "unknown gravity alignment code " + text(int(gravity_alignment));
  }
  return "";
}

/// `corrected`, when given, is written as the keyframe's pose, marked corrected.
void encodeKeyframe(const Keyframe& k, std::uint32_t session, const std::optional<Eigen::Isometry3d>& corrected,
                    ByteWriter* out) {
  out->f64(k.info.stamp);
  out->u32(session);
  out->i64(k.info.tag);
  out->f64(k.path_length);
  const std::optional<Eigen::Isometry3d>& pose = corrected ? corrected : k.info.pose;
  out->u8(!pose ? kNoPose : corrected || k.corrected_pose ? kCorrectedPose : kOdometryPose);
  if (pose) {
    for (int r = 0; r < kPoseRows; ++r) {
      for (int c = 0; c < 4; ++c) out->f64(pose->matrix()(r, c));
    }
  }
  const Descriptor& d = k.descriptor;
  out->u32(static_cast<std::uint32_t>(d.occupied_columns));
  out->bytes(d.unit_columns.data(), d.unit_columns.size());
  out->bytes(d.column_occupied.data(), d.column_occupied.size());
  out->f32s(d.ring_key.data(), d.ring_key.size());
  out->f32s(d.sector_key.data(), d.sector_key.size());
}

/// A keyframe record: stamp, session, tag, path length and the pose flag; the pose; the descriptor.
constexpr std::size_t kKeyframeHeadBytes = 8 + 4 + 8 + 8 + 1;
constexpr std::size_t kPoseBytes = kPoseRows * 4 * 8;
/// Version 1 stored the unit columns as f32, this version as i8 (Descriptor::unit_columns).
constexpr std::uint32_t kFloatColumnsVersion = 1;
std::size_t descriptorBytes(std::size_t rings, std::size_t sectors, std::uint32_t version = kDatabaseFileVersion) {
  const std::size_t column_entry = version == kFloatColumnsVersion ? 4 : 1;
  return 4 + column_entry * rings * sectors + sectors + 4 * rings + 4 * sectors;
}

/// Descriptors of a database whose arrays take less than this go on the heap, not in a BlockArena of
/// their own (a 2 MB block at least, doc/multi_robot.md: a team's records).
constexpr std::size_t kArenaMinBytes = std::size_t(1) << 20;

/// What a decoded descriptor's arrays take in a BlockArena at most (each aligned as malloc aligns).
std::size_t descriptorMemory(std::size_t rings, std::size_t sectors) {
  return descriptorBytes(rings, sectors) + 4 * alignof(std::max_align_t);
}

/// The payload as it is read: every piece taken goes into its checksum.
class PayloadReader {
 public:
  PayloadReader(ByteSource* file, std::uint64_t size) : file_(file), left_(size) {}
  /// *out reads the next `n` bytes; false when the payload or the file ends before them.
  bool take(std::size_t n, ByteReader* out) {
    const std::uint8_t* p = n <= left_ ? file_->take(n) : nullptr;
    if (p == nullptr) return false;
    crc_ = crc32(p, n, crc_);
    left_ -= n;
    *out = ByteReader(p, n);
    return true;
  }
  /// Reads the rest, for the checksum.
  bool drain() {
    ByteReader ignored(nullptr, 0);
    while (left_ > 0) {
      if (!take(static_cast<std::size_t>(std::min<std::uint64_t>(left_, kChunkBytes)), &ignored)) return false;
    }
    return true;
  }
  std::uint64_t left() const { return left_; }
  std::uint32_t crc() const { return crc_; }

 private:
  ByteSource* file_;
  std::uint64_t left_;
  std::uint32_t crc_ = 0;
};

const char* const kKeyframeOverrun = "the payload ends inside this keyframe's record: the counts and sizes disagree";

/// Reads a version-1 file's f32 unit columns into `d`'s int8 ones, quantised as makeDescriptor does;
/// returns what is wrong with them, or "".
std::string readFloatColumns(ByteReader* in, int rings, std::vector<float>* scratch, Descriptor* d) {
  scratch->resize(d->unit_columns.size());
  in->f32s(scratch->data(), scratch->size());
  // A unit column's entries lie in [-1, 1]; anything else is refused before it is rounded to int8.
  const double bound = 1.0 + kUnitColumnTolerance;
  const auto bad =
      std::find_if(scratch->begin(), scratch->end(), [bound](float v) { return !(std::fabs(v) <= bound); });
  if (bad != scratch->end()) {
    return "unit column entry " + text(bad - scratch->begin()) + " is " + text(*bad) + ", not within [-1, 1]";
  }
  for (std::size_t i = 0; i < d->unit_columns.size(); i += static_cast<std::size_t>(rings)) {
    quantiseUnitColumn(scratch->data() + i, rings, d->unit_columns.data() + i);
  }
  return "";
}

/// Decodes one keyframe record of a file of `version`; returns what is wrong with it, or "".
std::string decodeKeyframe(PayloadReader* payload, std::uint32_t version, int rings, int sectors, RingKeyType ring_key,
                           std::vector<float>* scratch, Keyframe* k) {
  ByteReader in(nullptr, 0);
  std::uint8_t has_pose = 0;
  if (!payload->take(kKeyframeHeadBytes, &in)) return kKeyframeOverrun;
  in.f64(&k->info.stamp);
  in.u32(&k->session);
  in.i64(&k->info.tag);
  in.f64(&k->path_length);
  in.u8(&has_pose);
  if (has_pose > kCorrectedPose) return "pose flag " + text(int(has_pose)) + " is not 0, 1 or 2";
  k->corrected_pose = has_pose == kCorrectedPose;
  if (has_pose != kNoPose) {
    if (!payload->take(kPoseBytes, &in)) return kKeyframeOverrun;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (int r = 0; r < kPoseRows; ++r) {
      for (int c = 0; c < 4; ++c) in.f64(&pose.matrix()(r, c));
    }
    k->info.pose = pose;
  }
  if (!payload->take(descriptorBytes(rings, sectors, version), &in)) return kKeyframeOverrun;
  Descriptor& d = k->descriptor;
  d.num_rings = rings;
  d.num_sectors = sectors;
  const std::size_t cells = static_cast<std::size_t>(rings) * sectors;
  d.ring_key.resize(rings);
  d.sector_key.resize(sectors);
  std::uint32_t occupied = 0;
  in.u32(&occupied);
  if (version == kFloatColumnsVersion) {
    d.unit_columns.resize(cells);
    if (std::string problem = readFloatColumns(&in, rings, scratch, &d); !problem.empty()) return problem;
  } else {
    const auto* columns = reinterpret_cast<const std::int8_t*>(in.take(cells));
    d.unit_columns.assign(columns, columns + cells);  // no zeroing first
  }
  const std::uint8_t* columns = in.take(sectors);
  d.column_occupied.assign(columns, columns + sectors);
  in.f32s(d.ring_key.data(), d.ring_key.size());
  in.f32s(d.sector_key.data(), d.sector_key.size());
  d.occupied_columns = static_cast<int>(std::min<std::uint32_t>(occupied, INT_MAX));
  return descriptorImplausibility(d, ring_key);
}

void encodeCloud(const Eigen::Matrix3f& gravity_alignment, const VoxelCloud* cloud, ByteWriter* out) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out->f32(gravity_alignment(r, c));
  }
  out->u8(cloud ? 1 : 0);
  if (!cloud) return;
  ByteWriter raw;
  raw.f32s(cloud->means.empty() ? nullptr : cloud->means.front().data(), 3 * cloud->size());
  raw.bytes(cloud->normals.data(), 4 * cloud->size());
  std::vector<char> packed(static_cast<std::size_t>(LZ4_compressBound(static_cast<int>(raw.size()))));
  const int packed_bytes = LZ4_compress_default(reinterpret_cast<const char*>(raw.buffer().data()), packed.data(),
                                                static_cast<int>(raw.size()), static_cast<int>(packed.size()));
  out->u32(static_cast<std::uint32_t>(cloud->size()));
  out->u32(static_cast<std::uint32_t>(packed_bytes));
  out->bytes(packed.data(), static_cast<std::size_t>(packed_bytes));
}

/// How far R^T R of a saved gravity alignment rotation may stray from the identity (largest entry): a
/// rotation rounded to float stays below 1e-6.
constexpr double kSavedRotationTolerance = 1e-3;

/// The voxel settings a file's registration data were made with (the height extent is makeVoxelCloud's
/// own, the same in every build that reads this version).
VoxelOptions voxelOptionsOf(const FileSettings& settings) {
  VoxelOptions o;
  o.resolution = static_cast<float>(settings.voxel_leaf);
  o.max_range = static_cast<float>(settings.voxel_max_range);
  return o;
}

/// What makeVoxelCloud with `crop` cannot produce in a voxel, or "": a mean is an average of points inside
/// the crop (horizontally within max_range, heights in [min_z, max_z)), allowed one voxel edge of slack
/// for rounding; a normal is a unit vector quantised to 127, so at most 128 long.
std::string voxelProblem(const Eigen::Vector3f& mean, const std::array<std::int8_t, 4>& normal,
                         const VoxelOptions& crop) {
  if (!mean.allFinite()) return "its mean is not finite";
  const double slack = crop.resolution, reach = crop.max_range + slack;
  const double x = mean.x(), y = mean.y(), z = mean.z();
  if (x * x + y * y > reach * reach || z < crop.min_z - slack || z > crop.max_z + slack) {
    return "its mean (" + text(x) + ", " + text(y) + ", " + text(z) + ") lies outside the crop (verify_max_range " +
           text(crop.max_range) + ", heights " + text(crop.min_z) + " to " + text(crop.max_z) + " m)";
  }
  const int length2 = normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2];
  if (length2 > 128 * 128) return "its normal is longer than a unit vector";
  if (normal[3] < VoxelCloud::kPlanar || normal[3] > VoxelCloud::kScatter) {
    return "voxel shape code " + text(int(normal[3])) + " is not one of 1-4";
  }
  return "";
}

/// Decodes one keyframe's gravity alignment and registration data; returns what is wrong with them, or "".
std::string decodeCloud(PayloadReader* payload, const FileSettings& settings, Eigen::Matrix3f* gravity_alignment,
                        std::unique_ptr<VoxelCloud>* cloud, std::vector<std::uint8_t>* scratch) {
  const char* const overrun =
      "the payload ends inside this keyframe's registration data: the counts and sizes disagree";
  ByteReader in(nullptr, 0);
  std::array<float, 9> rows;
  std::uint8_t has_cloud = 0;
  if (!payload->take(rows.size() * sizeof(float) + 1, &in)) return overrun;
  in.f32s(rows.data(), rows.size());
  in.u8(&has_cloud);
  if (!std::all_of(rows.begin(), rows.end(), [](float v) { return std::isfinite(v); })) {
    return "the gravity alignment rotation holds a value that is not finite";
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) (*gravity_alignment)(r, c) = rows[3 * r + c];
  }
  const Eigen::Matrix3d rotation = gravity_alignment->cast<double>();
  if ((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > kSavedRotationTolerance ||
      !(rotation.determinant() > 0.0)) {
    return "the gravity alignment rotation is not a rotation (not orthonormal, or a mirror)";
  }
  if (has_cloud > 1) return "registration data flag " + text(int(has_cloud)) + " is neither 0 nor 1";
  if (!has_cloud) return "";
  std::uint32_t voxels = 0, packed_bytes = 0;
  if (!payload->take(8, &in)) return overrun;
  in.u32(&voxels);
  in.u32(&packed_bytes);
  const std::uint64_t raw_bytes = std::uint64_t(voxels) * kVoxelBytes;
  if (raw_bytes > static_cast<std::uint64_t>(INT_MAX) || packed_bytes > static_cast<std::uint32_t>(INT_MAX)) {
    return "registration data of " + text(voxels) + " voxels is larger than LZ4 handles";
  }
  // Every count is checked before memory is set aside for it. LZ4 expands at most 255-fold, and
  // compresses n bytes into LZ4_COMPRESSBOUND(n) at most.
  if (raw_bytes > 255 * std::uint64_t(packed_bytes) + 16) {
    return "registration data of " + text(voxels) + " voxels cannot come from " + text(packed_bytes) +
           " compressed bytes";
  }
  if (packed_bytes > static_cast<std::uint64_t>(LZ4_COMPRESSBOUND(raw_bytes))) {
    return text(packed_bytes) + " compressed bytes are more than LZ4 makes of " + text(voxels) + " voxels";
  }
  const VoxelOptions crop = voxelOptionsOf(settings);
  if (const std::size_t most = maxVoxels(crop); voxels > most) {
    return "registration data of " + text(voxels) + " voxels, more than the " + text(most) +
           " that verify_voxel_leaf " + text(settings.voxel_leaf) + " and verify_max_range " +
           text(settings.voxel_max_range) + " allow (a voxel a grid cell, a point at least each)";
  }
  if (!payload->take(packed_bytes, &in)) return overrun;
  const std::uint8_t* packed = in.take(packed_bytes);
  scratch->resize(static_cast<std::size_t>(raw_bytes));
  const int unpacked =
      LZ4_decompress_safe(reinterpret_cast<const char*>(packed), reinterpret_cast<char*>(scratch->data()),
                          static_cast<int>(packed_bytes), static_cast<int>(raw_bytes));
  if (unpacked != static_cast<int>(raw_bytes)) {
    return "registration data do not decompress to " + text(voxels) + " voxels";
  }
  auto out = std::make_unique<VoxelCloud>();
  out->resolution = static_cast<float>(settings.voxel_leaf);
  out->max_range = static_cast<float>(settings.voxel_max_range);
  out->means.resize(voxels);
  out->normals.resize(voxels);
  if (voxels > 0) {
    ByteReader raw(scratch->data(), scratch->size());
    raw.f32s(out->means.front().data(), 3 * std::size_t(voxels));
    std::memcpy(out->normals.data(), raw.take(4 * std::size_t(voxels)), 4 * std::size_t(voxels));
  }
  for (std::size_t i = 0; i < out->size(); ++i) {
    if (const std::string problem = voxelProblem(out->means[i], out->normals[i], crop); !problem.empty()) {
      return "voxel " + text(i) + ": " + problem;
    }
  }
  *cloud = std::move(out);
  return "";
}

/// Streams the payload to a sink (AtomicFileWriter, MemorySink) in pieces, keeping its size and checksum.
template <typename Sink>
class PayloadWriter {
 public:
  explicit PayloadWriter(Sink* file) : file_(file) {}
  ByteWriter* out() { return &buffer_; }
  bool flushIfFull(std::string* error) { return buffer_.size() < kChunkBytes || flush(error); }
  bool flush(std::string* error) {
    crc_ = crc32(buffer_.buffer().data(), buffer_.size(), crc_);
    bytes_ += buffer_.size();
    const bool ok = file_->write(buffer_.buffer().data(), buffer_.size(), error);
    buffer_.clear();
    return ok;
  }
  std::uint64_t bytes() const { return bytes_; }
  std::uint32_t crc() const { return crc_; }

 private:
  Sink* file_;
  ByteWriter buffer_;
  std::uint64_t bytes_ = 0;
  std::uint32_t crc_ = 0;
};

/// A database image in memory, written as AtomicFileWriter writes a file.
class MemorySink {
 public:
  bool write(const void* data, std::size_t size, std::string*) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + size);
    return true;
  }
  bool writeAt(std::size_t offset, const void* data, std::size_t size, std::string*) {
    std::memcpy(bytes_.data() + offset, data, size);  // within what was written (the header's placeholder)
    return true;
  }
  std::vector<std::uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<std::uint8_t> bytes_;
};

template <typename Target>
bool loadInto(const std::string& path, Target* target, std::string* error) {
  PriorSessions sessions;
  if (!readDatabaseFile(path, target->config(), &sessions, error)) return false;
  std::string why;
  if (target->appendSessions(std::move(sessions), &why)) return true;
  if (error) *error = path + ": " + why;
  return false;
}

/// False, with the reason, when `path` holds a file that is not empty and not a database of ours: a
/// save replaces an earlier database, never someone's other file.
bool mayReplace(const std::string& path, std::string* error) {
  FileReader file;
  std::string why;
  if (!file.open(path, &why) || file.size() == 0) return true;  // absent, a directory: the writer says
  const std::uint8_t* head = file.take(sizeof(kMagic));
  if (head != nullptr && std::memcmp(head, kMagic, sizeof(kMagic)) == 0) return true;
  if (error)
    *error = path + " exists and is not a Scan Context database (it does not begin with \"SCLDB\"): not replaced";
  return false;
}

}  // namespace

DatabaseSnapshot::DatabaseSnapshot(const LoopDetector& detector, bool include_clouds, std::shared_ptr<const void> owner)
    : DatabaseSnapshot(detector, include_clouds, std::move(owner), 0, detector.database().size()) {}

DatabaseSnapshot::DatabaseSnapshot(const LoopDetector& detector, bool include_clouds, std::shared_ptr<const void> owner,
                                   std::size_t first, std::size_t count)
    : config_(detector.config()), include_clouds_(include_clouds), owner_(std::move(owner)) {
  const Database& database = detector.database();
  const std::size_t begin = std::min(first, database.size());
  const std::size_t end = begin + std::min(count, database.size() - begin);
  keyframes_ = database.keyframesView(begin, end);
  if (!include_clouds) return;
  gravity_alignment_ = detector.gravityAlignments(begin, end);
  clouds_ = detector.cloudStore().share(begin, end);
  for (auto& cloud : clouds_) cloud.first -= begin;
}

void DatabaseSnapshot::holdCloudsWeakly() {
  for (const auto& [index, cloud] : clouds_) weak_clouds_.emplace_back(index, cloud);
  clouds_.clear();
}

DatabaseSnapshot DatabaseSnapshot::strengthened(bool* complete) const {
  DatabaseSnapshot out = *this;
  out.weak_clouds_.clear();
  *complete = true;
  for (const auto& [index, weak] : weak_clouds_) {
    if (std::shared_ptr<const VoxelCloud> cloud = weak.lock()) {
      out.clouds_.emplace_back(index, std::move(cloud));
    } else {
      *complete = false;
    }
  }
  return out;
}

template <typename Sink>
bool writeImage(const DatabaseSnapshot& snapshot, Sink* file, std::string* error) {
  const ChunkedLog<const Keyframe*>::View& keyframes = snapshot.keyframes_;
  Header header;
  header.settings = settingsOf(snapshot.config_, snapshot.include_clouds_);
  header.keyframes = keyframes.size();
  const std::vector<std::uint8_t> placeholder(kHeaderBytes, 0);
  if (!file->write(placeholder.data(), placeholder.size(), error)) return false;
  PayloadWriter<Sink> payload(file);
  // Empty without corrections; else a pose or none per keyframe.
  const std::vector<std::optional<Eigen::Isometry3d>> corrected =
      snapshot.corrections_ ? correctedSessionPoses(keyframes.toVector(), *snapshot.corrections_)
                            : std::vector<std::optional<Eigen::Isometry3d>>();
  const std::optional<Eigen::Isometry3d> uncorrected;
  // Sessions are numbered 0, 1, ... in the file, whatever their numbers in the database.
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    if (i == 0 || keyframes[i - 1]->session != keyframes[i]->session) ++header.sessions;
    encodeKeyframe(*keyframes[i], header.sessions - 1, corrected.empty() ? uncorrected : corrected[i], payload.out());
    if (!payload.flushIfFull(error)) return false;
  }
  auto stored = snapshot.clouds_.begin();
  for (std::size_t i = 0; snapshot.include_clouds_ && i < keyframes.size(); ++i) {
    const VoxelCloud* cloud = nullptr;
    if (stored != snapshot.clouds_.end() && stored->first == i) cloud = (stored++)->second.get();
    encodeCloud(snapshot.gravity_alignment_[i], cloud, payload.out());
    if (!payload.flushIfFull(error)) return false;
  }
  if (!payload.flush(error)) return false;
  header.payload_bytes = payload.bytes();
  header.payload_crc = payload.crc();
  const std::vector<std::uint8_t> head = encodeHeader(header);
  return file->writeAt(0, head.data(), head.size(), error);
}

bool writeDatabase(const DatabaseSnapshot& snapshot, const std::string& path, bool keep_backup, std::string* error,
                   const std::atomic<bool>* cancel) {
  if (!mayReplace(path, error)) return false;
  AtomicFileWriter file;
  if (!file.open(path, error)) return false;
  if (keep_backup) file.keepBackup(path + ".bak");
  file.cancelWhen(cancel);
  return writeImage(snapshot, &file, error) && file.commit(error);
}

std::vector<std::uint8_t> encodeDatabase(const DatabaseSnapshot& snapshot) {
  MemorySink sink;
  writeImage(snapshot, &sink, nullptr);
  return sink.take();
}

std::string compatibilityText(const Config& config, bool include_clouds) {
  const FileSettings ours = settingsOf(config, include_clouds);
  std::string out;
  for (const auto& row : settingRows(ours, ours)) out += (out.empty() ? "" : ", ") + row[0] + " " + row[1];
  return out;
}

bool saveDatabase(const LoopDetector& detector, const std::string& path, const SaveOptions& options,
                  std::string* error) {
  return writeDatabase(DatabaseSnapshot(detector, options.include_clouds), path, options.keep_backup, error);
}

bool readDatabaseFile(const std::string& path, const Config& config, PriorSessions* sessions, std::string* error) {
  FileReader file;
  return file.open(path, error) && readDatabase(&file, path, config, sessions, error);
}

bool readDatabase(ByteSource* source, const std::string& name, const Config& config, PriorSessions* sessions,
                  std::string* error) {
  const auto fail = [&](const std::string& why) {
    if (error) *error = name + ": " + why;
    return false;
  };
  ByteSource& file = *source;
  if (file.size() == 0) return fail("the file is empty");
  const std::size_t head_bytes = static_cast<std::size_t>(std::min<std::uint64_t>(file.size(), kHeaderBytes));
  const std::uint8_t* head = file.take(head_bytes);
  if (head == nullptr) return fail(file.readError());
  if (std::memcmp(head, kMagic, std::min(head_bytes, sizeof(kMagic))) != 0) {
    return fail("not a Scan Context database (it does not begin with \"SCLDB\")");
  }
  const std::string short_header =
      "truncated: " + text(file.size()) + " bytes, shorter than the " + text(kHeaderBytes) + "-byte header";
  ByteReader in(head, head_bytes);
  std::uint32_t version = 0;
  if (!in.take(sizeof(kMagic)) || !in.u32(&version)) return fail(short_header);
  if (version != kDatabaseFileVersion && version != kFloatColumnsVersion) {
    return fail("format version " + text(version) + ", but this build reads versions " + text(kFloatColumnsVersion) +
                " and " + text(kDatabaseFileVersion) + " only");
  }
  if (head_bytes < kHeaderBytes) return fail(short_header);
  ByteReader stored_crc(head + kHeaderBytes - 4, 4);
  std::uint32_t header_crc = 0;
  stored_crc.u32(&header_crc);
  if (crc32(head, kHeaderBytes - 4) != header_crc) return fail("header checksum mismatch: the header is corrupt");
  Header header;
  if (const std::string problem = decodeHeader(&in, &header); !problem.empty()) return fail(problem);
  const std::uint64_t payload_bytes = file.size() - kHeaderBytes;
  if (payload_bytes < header.payload_bytes) {
    return fail("truncated: " + text(file.size()) + " of the " + text(kHeaderBytes + header.payload_bytes) +
                " bytes the header gives");
  }
  if (payload_bytes > header.payload_bytes) {
    return fail(text(file.size()) + " bytes, more than the " + text(kHeaderBytes + header.payload_bytes) +
                " the header gives: something follows the payload");
  }
  if (const std::string problem = settingsMismatch(header.settings, settingsOf(config, header.settings.clouds));
      !problem.empty()) {
    return fail(problem);
  }
  const int rings = config.num_rings, sectors = config.num_sectors;
  if (header.keyframes > payload_bytes / (kKeyframeHeadBytes + descriptorBytes(rings, sectors, version))) {
    return fail("the header counts " + text(header.keyframes) + " keyframes, more than the " + text(payload_bytes) +
                "-byte payload can hold");
  }

  if (header.sessions > header.keyframes || (header.sessions == 0) != (header.keyframes == 0)) {
    return fail("the header counts " + text(header.sessions) + " sessions for " + text(header.keyframes) +
                " keyframes");
  }
  if (header.settings.clouds && maxVoxels(voxelOptionsOf(header.settings)) == 0) {
    return fail("the registration data's voxel settings (verify_voxel_leaf, verify_max_range) are not positive");
  }

  // One pass over the payload: records are decoded as they are read and checksummed on the way. A
  // damaged payload may first show as a record that makes no sense; the checksum over the whole payload
  // then says which it is.
  PayloadReader payload(&file, payload_bytes);
  const auto checked = [&](const std::string& problem) {
    if (!payload.drain()) return fail(file.readError().empty() ? "the file shrank while being read" : file.readError());
    if (payload.crc() != header.payload_crc) return fail("payload checksum mismatch: the file is corrupt");
    return problem.empty() || fail(problem);
  };
  PriorSessions loaded;
  loaded.keyframes.reserve(header.keyframes);
  adviseHugePages(loaded.keyframes.data(), header.keyframes * sizeof(Keyframe));
  // The descriptors' arrays, most of the memory, in one arena: far fewer page faults in a new process.
  // Both it and the records are set up by the kernel on another thread while the records are decoded
  // into them (PageWarmer). A few keyframes (a record a robot of a team shares, a keyframe's registration
  // data) go on the heap instead: an arena maps at least 2 MB, which each of them would keep alive.
  const std::size_t arena_bytes = header.keyframes * descriptorMemory(rings, sectors);
  const BlockArena::Handle arena = arena_bytes >= kArenaMinBytes ? BlockArena::create(arena_bytes) : nullptr;
  std::pmr::memory_resource* const memory = arena ? arena.get() : std::pmr::get_default_resource();
  const PageWarmer warmer({arena ? arena->reserve(arena_bytes) : BlockArena::Range(),
                           {reinterpret_cast<char*>(loaded.keyframes.data()), header.keyframes * sizeof(Keyframe)}});
  std::vector<float> float_columns;  // a version-1 record's unit columns before they are quantised
  for (std::size_t i = 0; i < header.keyframes; ++i) {
    Keyframe& k = loaded.keyframes.emplace_back(Keyframe{KeyframeInfo(), Descriptor(memory), 0.0, 0, false});
    if (const std::string problem =
            decodeKeyframe(&payload, version, rings, sectors, header.settings.ring_key, &float_columns, &k);
        !problem.empty()) {
      return checked("keyframe " + text(i) + ": " + problem);
    }
  }
  const std::uint32_t sessions_found = loaded.keyframes.empty() ? 0 : loaded.keyframes.back().session + 1;
  if (sessions_found != header.sessions) {
    return checked("the header counts " + text(header.sessions) + " sessions, but the keyframes number " +
                   text(sessions_found));
  }
  if (header.settings.clouds) {
    loaded.gravity_alignment.resize(loaded.keyframes.size());
    loaded.clouds.resize(loaded.keyframes.size());
    std::vector<std::uint8_t> scratch;
    for (std::size_t i = 0; i < loaded.keyframes.size(); ++i) {
      const std::string problem =
          decodeCloud(&payload, header.settings, &loaded.gravity_alignment[i], &loaded.clouds[i], &scratch);
      if (!problem.empty()) return checked("keyframe " + text(i) + ": " + problem);
    }
  }
  if (payload.left() != 0) {
    return checked(text(payload.left()) +
                   " bytes of the payload follow the last record: the counts and sizes disagree");
  }
  if (!checked("")) return false;
  loaded.descriptors_checked = true;
  *sessions = std::move(loaded);
  return true;
}

bool loadDatabase(const std::string& path, LoopDetector* detector, std::string* error) {
  return loadInto(path, detector, error);
}

bool loadDatabase(const std::string& path, KeyframePipeline* pipeline, std::string* error) {
  return loadInto(path, pipeline, error);
}

}  // namespace scan_context_loop
