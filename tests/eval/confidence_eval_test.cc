// Confidence scores (eval/confidence_eval.h) on hand-computed cases: the reliability bins, the expected
// calibration error, the AUROC with ties, the shares above 0.5 and 0.8; NaN skipped, all-right without AUROC.
#include "eval/confidence_eval.h"

#include <gtest/gtest.h>

#include <cmath>

namespace semvox {
namespace {

// Bins: [0.0, 0.1) one wrong at 0.05; [0.1, 0.2) one wrong at 0.15; [0.5, 0.6) one right and one wrong at 0.55;
// [0.9, 1.0] two right at 0.95. ECE = (0.05 + 0.15 + 2 * 0.05 + 2 * 0.05) / 6. AUROC: the two right at 0.95 beat
// all three wrong (6 pairs), the right one at 0.55 beats two and ties one (2.5): 8.5 / 9.
TEST(ConfidenceScores, HandComputedCase) {
  const ConfidenceScores s = ScoreConfidence({0.05f, 0.15f, 0.95f, 0.95f, 0.55f, 0.55f, NAN}, {0, 0, 1, 1, 1, 0, 1});
  EXPECT_EQ(s.scored, 6u);
  EXPECT_NEAR(s.ece.value, 0.4 / 6.0, 1e-6);
  ASSERT_TRUE(s.auroc.present);
  EXPECT_NEAR(s.auroc.value, 8.5 / 9.0, 1e-12);
  EXPECT_NEAR(s.accuracy.value, 0.5, 1e-12);
  EXPECT_NEAR(s.mean_confidence.value, (0.05 + 0.15 + 0.95 * 2 + 0.55 * 2) / 6.0, 1e-6);
  EXPECT_EQ(s.bins[0].count, 1u);
  EXPECT_EQ(s.bins[1].count, 1u);
  EXPECT_EQ(s.bins[5].count, 2u);
  EXPECT_NEAR(s.bins[5].accuracy, 0.5, 1e-12);
  EXPECT_EQ(s.bins[9].count, 2u);
  EXPECT_NEAR(s.bins[9].mean_confidence, 0.95, 1e-6);
  EXPECT_NEAR(s.share_above_05.value, 4.0 / 6.0, 1e-12);
  EXPECT_NEAR(s.accuracy_above_05.value, 0.75, 1e-12);
  EXPECT_NEAR(s.share_above_08.value, 2.0 / 6.0, 1e-12);
  EXPECT_NEAR(s.accuracy_above_08.value, 1.0, 1e-12);
  EXPECT_NE(ConfidenceTable(s).find("ECE"), std::string::npos);
}

// Confidence that ranks wrong above right gives an AUROC under a half; 1.0 lands in the last bin; every prediction
// right has no AUROC; nothing scored has no score at all.
TEST(ConfidenceScores, EdgeCases) {
  ConfidenceScores s = ScoreConfidence({0.9f, 0.2f, 1.0f, 1.5f}, {0, 1, 0, 0});
  ASSERT_TRUE(s.auroc.present);
  EXPECT_DOUBLE_EQ(s.auroc.value, 0.0);
  EXPECT_EQ(s.bins[9].count, 3u);  // 0.9, 1.0 and 1.5 (clamped).
  s = ScoreConfidence({0.3f, 0.7f}, {1, 1});
  EXPECT_FALSE(s.auroc.present);
  EXPECT_NEAR(s.ece.value, 0.5, 1e-6);  // |1 - 0.3| / 2 + |1 - 0.7| / 2.
  s = ScoreConfidence({}, {});
  EXPECT_EQ(s.scored, 0u);
  EXPECT_FALSE(s.ece.present);
}

}  // namespace
}  // namespace semvox
