// Readers for the corrected map's text files (graph/map_files.h), written as other tools read them:
// TUM as evo reads it (8 numbers a line, '#' comments, stamps increasing), KITTI (12 numbers a line),
// and the SE3 part of a g2o file. Each flags what does not fit with a gtest failure.
#pragma once

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace scan_context_loop {
namespace test {

using Matrix6 = Eigen::Matrix<double, 6, 6>;

inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The lines of a text file that are not empty and not '#' comments, split at whitespace.
inline std::vector<std::vector<std::string>> rows(const std::string& path) {
  std::vector<std::vector<std::string>> out;
  std::istringstream in(readText(path));
  std::string line;
  while (std::getline(in, line)) {
    const std::size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream words(line);
    std::vector<std::string> row;
    for (std::string word; words >> word;) row.push_back(word);
    out.push_back(row);
  }
  return out;
}

inline double number(const std::string& word) {
  std::size_t used = 0;
  const double value = std::stod(word, &used);
  EXPECT_EQ(used, word.size()) << "not a number: " << word;
  return value;
}

inline Eigen::Isometry3d poseOf(const std::vector<std::string>& row, std::size_t first) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << number(row[first]), number(row[first + 1]), number(row[first + 2]);
  const Eigen::Quaterniond q(number(row[first + 6]), number(row[first + 3]), number(row[first + 4]),
                             number(row[first + 5]));
  EXPECT_NEAR(q.norm(), 1.0, 1e-12);
  pose.linear() = q.normalized().toRotationMatrix();
  return pose;
}

inline double poseDifference(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff();
}

/// A TUM trajectory as evo reads one: 8 numbers a line (stamp tx ty tz qx qy qz qw), '#' comments,
/// stamps increasing.
struct Tum {
  std::vector<double> stamps;
  std::vector<std::string> stamp_text;
  std::vector<Eigen::Isometry3d> poses;
};

inline Tum readTum(const std::string& path) {
  Tum tum;
  for (const auto& row : rows(path)) {
    EXPECT_EQ(row.size(), 8u) << path;
    if (row.size() != 8) continue;
    tum.stamps.push_back(number(row[0]));
    tum.stamp_text.push_back(row[0]);
    if (tum.stamps.size() > 1) {
      EXPECT_GT(tum.stamps.back(), tum.stamps[tum.stamps.size() - 2]) << path;
    }
    tum.poses.push_back(poseOf(row, 1));
  }
  return tum;
}

/// A KITTI trajectory: 12 numbers a line, rows 0-2 of the 4x4 pose.
inline std::vector<Eigen::Isometry3d> readKitti(const std::string& path) {
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& row : rows(path)) {
    EXPECT_EQ(row.size(), 12u) << path;
    if (row.size() != 12) continue;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (int i = 0; i < 12; ++i) pose.matrix()(i / 4, i % 4) = number(row[i]);
    poses.push_back(pose);
  }
  return poses;
}

/// A g2o file's SE3 part: vertices, edges (with the full information matrix from its upper triangle) and
/// the fixed vertices; any other tag fails the test.
struct G2o {
  std::map<long, Eigen::Isometry3d> vertices;
  struct Edge {
    long a, b;
    Eigen::Isometry3d measurement;
    Matrix6 information;
  };
  std::vector<Edge> edges;
  std::vector<long> fixed;
};

inline G2o readG2o(const std::string& path) {
  G2o g;
  for (const auto& row : rows(path)) {
    if (row[0] == "VERTEX_SE3:QUAT") {
      EXPECT_EQ(row.size(), 9u);
      if (row.size() != 9) continue;
      EXPECT_EQ(g.vertices.count(std::stol(row[1])), 0u) << "vertex " << row[1] << " twice";
      g.vertices[std::stol(row[1])] = poseOf(row, 2);
    } else if (row[0] == "EDGE_SE3:QUAT") {
      EXPECT_EQ(row.size(), 31u) << "an edge line holds 30 numbers";
      if (row.size() != 31) continue;
      G2o::Edge edge{std::stol(row[1]), std::stol(row[2]), poseOf(row, 3), Matrix6::Zero()};
      std::size_t k = 10;
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) edge.information(r, c) = edge.information(c, r) = number(row[k++]);
      }
      g.edges.push_back(edge);
    } else if (row[0] == "FIX") {
      for (std::size_t i = 1; i < row.size(); ++i) g.fixed.push_back(std::stol(row[i]));
    } else {
      ADD_FAILURE() << "unknown g2o tag " << row[0];
    }
  }
  return g;
}

}  // namespace test
}  // namespace scan_context_loop
