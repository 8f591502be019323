// The graph study (eval/graph_study.h): the evaluator's pose graph solved again per variant.
#include "scan_context_loop/eval/graph_study.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "correction_graph.h"
#include "scan_context_loop/core/settings.h"
#include "scan_context_loop/graph/pose_graph_settings.h"

namespace scan_context_loop {
namespace eval {

namespace {

bool setStudyKey(const std::string& key, const std::string& value, GraphVariant* v, std::string* error) {
  if (key == "loops") {
    if (value == "reported") v->loops = GraphVariant::Loops::kReported;
    else if (value == "reported_true") v->loops = GraphVariant::Loops::kReportedTrue;
    else if (value == "oracle") v->loops = GraphVariant::Loops::kOracle;
    else if (value == "none") v->loops = GraphVariant::Loops::kNone;
    else return (*error = "loops must be reported, reported_true, oracle or none"), false;
    return true;
  }
  if (key == "covariance") {
    if (value != "reported" && value != "floor") return (*error = "covariance must be reported or floor"), false;
    v->floor_covariance = value == "floor";
    return true;
  }
  if (key == "covariance_scale") {
    char* end = nullptr;
    v->covariance_scale = std::strtod(value.c_str(), &end);
    if (end == value.c_str() || *end != '\0' || !(v->covariance_scale > 0.0) || !std::isfinite(v->covariance_scale))
      return (*error = "covariance_scale must be a number > 0"), false;
    return true;
  }
  if (key == "false_loop") {
    if (value != "0" && value != "1") return (*error = "false_loop must be 0 or 1"), false;
    v->false_loop = value == "1";
    return true;
  }
  const Setting<PoseGraphConfig>* row = findSetting(poseGraphSettings(), key);
  if (row == nullptr) return (*error = "unknown key " + key), false;
  if (!row->set(&v->graph, value)) return (*error = key + " must be " + settingTypeName(row->type, row->choices)), false;
  const std::string rule = row->check(v->graph);
  if (!rule.empty()) return (*error = key + " " + rule), false;
  return true;
}

/// RMSE after the best similarity (rotation, translation and scale: what loops cannot see, the
/// odometry's common scale error, taken out too), and that scale.
double similarityRmse(const std::vector<Eigen::Isometry3d>& estimate, const std::vector<Eigen::Isometry3d>& truth,
                      double* scale) {
  *scale = 1.0;
  if (estimate.size() != truth.size() || estimate.size() < 3) return 0.0;
  const Eigen::Index n = static_cast<Eigen::Index>(estimate.size());
  Eigen::Matrix3Xd from(3, n), to(3, n);
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    from.col(static_cast<Eigen::Index>(i)) = estimate[i].translation();
    to.col(static_cast<Eigen::Index>(i)) = truth[i].translation();
  }
  const Eigen::Matrix4d t = Eigen::umeyama(from, to, true);
  *scale = t.topLeftCorner<3, 3>().determinant() > 0.0 ? std::cbrt(t.topLeftCorner<3, 3>().determinant()) : 0.0;
  Eigen::Matrix3Xd moved = t.topLeftCorner<3, 3>() * from;
  moved.colwise() += Eigen::Vector3d(t.topRightCorner<3, 1>());
  return std::sqrt((moved - to).colwise().squaredNorm().sum() / static_cast<double>(from.cols()));
}

}  // namespace

bool parseGraphVariant(const std::string& line, GraphVariant* variant, std::string* error) {
  error->clear();
  std::istringstream in(line);
  GraphVariant v;
  if (!(in >> v.name) || v.name[0] == '#') return false;
  for (std::string word; in >> word;) {
    const auto eq = word.find('=');
    if (eq == std::string::npos) return (*error = v.name + ": expected KEY=VALUE, got " + word), false;
    if (!setStudyKey(word.substr(0, eq), word.substr(eq + 1), &v, error)) return (*error = v.name + ": " + *error), false;
    v.text += (v.text.empty() ? "" : " ") + word;
  }
  *variant = v;
  return true;
}

bool readGraphVariants(const std::string& path, std::vector<GraphVariant>* variants, std::string* error) {
  std::ifstream in(path);
  if (!in) return (*error = "cannot read " + path), false;
  variants->clear();
  for (std::string line; std::getline(in, line);) {
    GraphVariant v;
    if (parseGraphVariant(line, &v, error)) {
      variants->push_back(v);
    } else if (!error->empty()) {
      *error = path + ": " + *error;
      return false;
    }
  }
  return true;
}

std::vector<bool> revisitedKeyframes(const Sequence& s, const Evaluation& e) {
  std::vector<bool> flags(s.frames.size(), false);
  std::vector<long> keyframe_of_frame;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    if (s.frames[k] < 0) continue;
    if (static_cast<std::size_t>(s.frames[k]) >= keyframe_of_frame.size()) keyframe_of_frame.resize(s.frames[k] + 1, -1);
    keyframe_of_frame[static_cast<std::size_t>(s.frames[k])] = static_cast<long>(k);
  }
  for (const QueryOutcome& o : e.outcomes) {
    if (o.revisit_index < 0 || o.query < 0 || static_cast<std::size_t>(o.query) >= keyframe_of_frame.size()) continue;
    const long q = keyframe_of_frame[static_cast<std::size_t>(o.query)];
    if (q >= 0) flags[static_cast<std::size_t>(q)] = true;
    const std::size_t index = static_cast<std::size_t>(o.revisit_index);
    const long m = index < e.keyframe_of.size() ? e.keyframe_of[index] : -1;  // -1 for a prior map's keyframe
    if (m >= 0) flags[static_cast<std::size_t>(m)] = true;
  }
  return flags;
}

std::vector<GraphStudyRow> runGraphStudy(const Sequence& s, const Evaluation& e, const Config& config,
                                         const std::vector<GraphVariant>& variants) {
  std::vector<GraphVariant> all(1);
  all[0].name = "odometry";
  all[0].text = "loops=none";
  all[0].loops = GraphVariant::Loops::kNone;
  all.insert(all.end(), variants.begin(), variants.end());
  const std::vector<bool> revisited = revisitedKeyframes(s, e);
  std::vector<GraphStudyRow> rows;
  for (const GraphVariant& v : all) {
    GraphStudyRow row;
    row.name = v.name;
    row.text = v.text;
    CorrectionGraph g(s, e, v.graph);
    if (!g.ok() || s.odometry.size() < 3) continue;
    const LoopCovariance covariance = v.floor_covariance ? LoopCovariance::kFloor : LoopCovariance::kReported;
    switch (v.loops) {
      case GraphVariant::Loops::kReported:
        row.loops = g.addReportedLoops(config, LoopPose::kMeasured, covariance, v.covariance_scale);
        break;
      case GraphVariant::Loops::kReportedTrue:
        row.loops = g.addReportedLoops(config, LoopPose::kTrue, covariance, v.covariance_scale);
        break;
      case GraphVariant::Loops::kOracle:
        row.loops = g.addOracleLoops(v.covariance_scale * floorCovariance(config));
        break;
      case GraphVariant::Loops::kNone:
        break;
    }
    if (v.false_loop) g.addFalseLoop(v.covariance_scale * floorCovariance(config));
    const PoseGraphResult result = g.graph.optimize();
    row.solved = result.solved;
    row.iterations = result.iterations;
    row.seconds = result.seconds;
    const std::vector<Eigen::Isometry3d> poses = g.sequencePoses();
    row.aligned = absoluteTrajectoryError(poses, s.truth);
    row.anchored = positionError(poses, s.truth);
    row.similarity_rmse = similarityRmse(poses, s.truth, &row.similarity_scale);
    row.revisited = partError(poses, s.truth, row.aligned.alignment, revisited, true);
    row.rest = partError(poses, s.truth, row.aligned.alignment, revisited, false);
    rows.push_back(row);
  }
  return rows;
}

bool writeGraphStudyCsv(const std::string& path, const std::vector<GraphStudyRow>& rows, std::string* error) {
  std::ofstream out(path);
  if (!out) return (*error = "cannot create " + path), false;
  out.precision(6);
  out << "variant,loops,solved,iterations,seconds,ate_rmse_m,ate_max_m,revisited_rmse_m,revisited_keyframes,"
         "rest_rmse_m,rest_keyframes,similarity_rmse_m,similarity_scale,anchored_rmse_m,settings\n";
  for (const GraphStudyRow& r : rows) {
    out << r.name << ',' << r.loops << ',' << r.solved << ',' << r.iterations << ',' << r.seconds << ','
        << r.aligned.rmse << ',' << r.aligned.max << ',' << r.revisited.rmse << ',' << r.revisited.keyframes << ','
        << r.rest.rmse << ',' << r.rest.keyframes << ',' << r.similarity_rmse << ',' << r.similarity_scale << ','
        << r.anchored.rmse << ",\"" << r.text << "\"\n";
  }
  if (!out.good()) return (*error = "cannot write " + path), false;
  return true;
}

}  // namespace eval
}  // namespace scan_context_loop
