// Relocalization in a prior map given as a saved database (scan_context_evaluate --prior FILE
// --prior-truth DIR): the same outcomes as with the prior sequence itself, and clear refusals.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "scan_context_loop/eval/evaluation.h"
#include "scan_context_loop/eval/prior_map.h"
#include "../common/sim_drive.h"
#include "../common/written_sequence.h"

namespace scan_context_loop {
namespace eval {
namespace {

std::string priorTemp(const std::string& name) { return testing::TempDir() + "/scl_dbprior_" + name; }

/// Two sessions of one block (test::blockSessions): the prior lap, and the query driven back the other way
/// one lane over with cars and plants changed, its first 30 keyframes only.
struct Fixture {
  Sequence prior, query;
  std::string database = priorTemp("prior.scldb");
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture f;
    const test::Sessions sessions = test::blockSessions(3);
    f.prior = test::writtenSequence(sessions.first, priorTemp("prior"), 11, 0.0);
    test::writtenSequence(sessions.second, priorTemp("query"), 12, 0.0);
    SequenceOptions window;
    window.last = 29;
    std::string error;
    EXPECT_TRUE(loadSequence(priorTemp("query"), window, &f.query, &error)) << error;
    // A mapping run: the prior evaluated on its own, its database saved with the registration data.
    EvaluationOptions mapping;
    mapping.save_database = f.database;
    mapping.save_clouds = true;
    Evaluation e;
    EXPECT_TRUE(evaluate(f.prior, Config(), mapping, &e, &error)) << error;
    return f;
  }();
  return f;
}

/// Evaluates `query` in the prior map (a database's keyframes move into the evaluation's pipeline) and
/// saves the database at the end to `save` unless it is empty.
Evaluation evaluateIn(PriorMap* map, const Sequence& query, const std::string& save = "") {
  EvaluationOptions options;
  options.save_database = save;
  if (map->kind == PriorMap::Kind::kSequence) options.prior = &map->sequence;
  if (map->kind == PriorMap::Kind::kDatabase) options.prior_database = &map->database;
  Evaluation e;
  std::string error;
  EXPECT_TRUE(evaluate(query, Config(), options, &e, &error)) << error;
  return e;
}

TEST(DatabasePrior, RelocalizesAsThePriorSequenceDoes) {
  const Fixture& f = fixture();
  ASSERT_EQ(f.query.frames.size(), 30u);
  std::string error;
  PriorMap sequence, database;
  ASSERT_TRUE(loadPriorMap(f.prior.dir, "", SequenceOptions(), Config(), &sequence, &error)) << error;
  ASSERT_EQ(sequence.kind, PriorMap::Kind::kSequence);
  ASSERT_TRUE(loadPriorMap(f.database, f.prior.dir, SequenceOptions(), Config(), &database, &error)) << error;
  ASSERT_EQ(database.kind, PriorMap::Kind::kDatabase);
  // Every keyframe of the prior, tagged with its frame, with the true pose of that frame.
  ASSERT_EQ(database.database.keyframes.frames, f.prior.frames);
  for (std::size_t k = 0; k < f.prior.frames.size(); ++k) {
    ASSERT_TRUE(database.database.keyframes.truth[k].isApprox(f.prior.truth[k])) << k;
  }
  ASSERT_EQ(database.database.sessions.clouds.size(), f.prior.frames.size());

  const Evaluation a = evaluateIn(&sequence, f.query, priorTemp("both.scldb"));
  const Evaluation b = evaluateIn(&database, f.query);
  ASSERT_TRUE(a.has_prior && b.has_prior);
  EXPECT_EQ(b.prior_source, f.database);
  EXPECT_EQ(b.prior_truth, f.prior.dir);
  EXPECT_EQ(a.relocalization.prior_keyframes, b.relocalization.prior_keyframes);
  ASSERT_EQ(a.prior_outcomes.size(), f.query.frames.size());
  ASSERT_EQ(b.prior_outcomes.size(), a.prior_outcomes.size());
  for (std::size_t i = 0; i < a.prior_outcomes.size(); ++i) {
    const PriorOutcome& x = a.prior_outcomes[i];
    const PriorOutcome& y = b.prior_outcomes[i];
    EXPECT_EQ(x.query, y.query);
    EXPECT_EQ(x.nearest, y.nearest) << x.query;
    EXPECT_EQ(x.match, y.match) << x.query;
    EXPECT_EQ(x.correct, y.correct) << x.query;
    EXPECT_NEAR(x.translation_error, y.translation_error, 0.01) << x.query;
  }
  const RelocalizationMetrics& r = b.relocalization;
  EXPECT_EQ(r.true_positives, a.relocalization.true_positives);
  EXPECT_EQ(r.false_positives, a.relocalization.false_positives);
  EXPECT_EQ(r.first_query, a.relocalization.first_query);
  // Not vacuous: the query relocalizes, and never wrongly.
  EXPECT_GE(r.true_positives, 10u);
  EXPECT_EQ(r.false_positives, 0u);

  // The database of that evaluation holds both sessions: one sequence's truth cannot score it.
  PriorMap both;
  EXPECT_FALSE(loadPriorMap(priorTemp("both.scldb"), f.prior.dir, SequenceOptions(), Config(), &both, &error));
  EXPECT_NE(error.find("holds 2 sessions"), std::string::npos) << error;
}

TEST(DatabasePrior, RefusesWithoutItsTruthOrWithAnotherConfiguration) {
  const Fixture& f = fixture();
  PriorMap map;
  std::string error;
  EXPECT_FALSE(loadPriorMap(f.database, "", SequenceOptions(), Config(), &map, &error));
  EXPECT_NE(error.find("--prior-truth"), std::string::npos) << error;

  Config other;
  other.num_sectors = 90;
  EXPECT_FALSE(loadPriorMap(f.database, f.prior.dir, SequenceOptions(), other, &map, &error));
  EXPECT_NE(error.find("num_sectors"), std::string::npos) << error;

  // A truth sequence that is not the database's: too few frames for its tags.
  const std::string shorter = priorTemp("shorter");
  std::filesystem::create_directories(shorter);
  std::filesystem::copy_file(f.prior.dir + "/calib.txt", shorter + "/calib.txt",
                             std::filesystem::copy_options::overwrite_existing);
  std::ifstream poses(f.prior.dir + "/poses.txt");
  std::ofstream three(shorter + "/poses.txt");
  std::string line;
  for (int i = 0; i < 3 && std::getline(poses, line); ++i) three << line << '\n';
  three.close();
  EXPECT_FALSE(loadPriorMap(f.database, shorter, SequenceOptions(), Config(), &map, &error));
  EXPECT_NE(error.find("no frame of " + shorter), std::string::npos) << error;

  // A truth sequence with a sequence prior, and a prior that does not exist.
  EXPECT_FALSE(loadPriorMap(f.prior.dir, f.prior.dir, SequenceOptions(), Config(), &map, &error));
  EXPECT_NE(error.find("database file only"), std::string::npos) << error;
  EXPECT_FALSE(loadPriorMap(priorTemp("absent"), f.prior.dir, SequenceOptions(), Config(), &map, &error));
  EXPECT_NE(error.find("no such file"), std::string::npos) << error;
}

}  // namespace
}  // namespace eval
}  // namespace scan_context_loop
