// Backing a rejected candidate off towards the unreduced model (reduction/verification_back_off.h)
// and the share a merged or plain reduction keeps (reduction/merge_reduction.h).
#include <gtest/gtest.h>

#include <vector>

#include "thermodec/reduction/merge_reduction.h"
#include "thermodec/reduction/verification_back_off.h"

using namespace thermodec;

TEST(VerificationBackOff, bisects_towards_the_largest_accepted_scale) {
  // Accepted up to 0.6: 1/2 accepted, 3/4 rejected, 5/8 rejected.
  std::vector<double> asked;
  const double s = back_off_scale(3, [&](double a) {
    asked.push_back(a);
    return a <= 0.6;
  });
  EXPECT_EQ(asked, (std::vector<double>{0.5, 0.75, 0.625}));
  EXPECT_DOUBLE_EQ(s, 0.5);
}

TEST(VerificationBackOff, nothing_accepted_or_no_steps_gives_the_unreduced_model) {
  std::vector<double> asked;
  EXPECT_DOUBLE_EQ(back_off_scale(2, [&](double a) { asked.push_back(a); return false; }), 0.0);
  EXPECT_EQ(asked, (std::vector<double>{0.5, 0.25}));
  EXPECT_DOUBLE_EQ(back_off_scale(0, [](double) { return true; }), 0.0);
  EXPECT_DOUBLE_EQ(back_off_scale(-1, [](double) { return true; }), 0.0);
}

TEST(VerificationBackOff, every_scale_accepted_climbs_towards_the_rejected_candidate) {
  EXPECT_DOUBLE_EQ(back_off_scale(2, [](double) { return true; }), 0.75);
}

TEST(KeptShare, weighs_nodes_and_faces_alike) {
  // NPP_16: merged to 34 of 64 nodes with every face, against the plain decimation's 29 %.
  EXPECT_NEAR(kept_share(64, 34, 3965, 3965), 34.0 / 64 + 1.0, 1e-12);
  EXPECT_LT(kept_share(64, 64, 3965, 1135), kept_share(64, 34, 3965, 3965));
  EXPECT_LT(kept_share(64, 34, 3965, 2000), kept_share(64, 64, 3965, 1135));
  EXPECT_DOUBLE_EQ(kept_share(0, 0, 0, 0), 0.0);
}
