// law_support::consistent_sigma, the solve that makes a law's strength consistent with the normal
// stress after the increment's dilation, against closed forms of the map it solves. The map of a
// slipping Mohr-Coulomb joint at a constant rate is linear, step(s) = s_tr + c (s - s_ref), with
// c = kn |rate| tan(phi) / ks (theory/effects.md, "Contraction on a stiff closure curve"); its
// fixed point is (c s_ref - s_tr) / (c - 1).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "framework/plugin_api/law_support.hpp"

using rockdem::law_support::consistent_sigma;

namespace {

// A linear step map, optionally with its output rounded to `quantum` Pa (what a law's arithmetic
// does at MPa stresses, coarser here so that the test does not depend on the last bits). Records
// its calls so that the contract (the last call is step(answer)) can be checked.
struct LinearStep {
  double trial, c, ref, quantum = 0.0;
  std::vector<double> calls;
  double operator()(double s) {
    calls.push_back(s);
    const double out = trial + c * (s - ref);
    return quantum > 0.0 ? std::round(out / quantum) * quantum : out;
  }
  double root() const { return (c * ref - trial) / (c - 1.0); }
};

}  // namespace

TEST(ConsistentSigma, SolvesAContractingMapWhoseTrialStressIsFarBelowTheAnswer) {
  // A strongly contracting increment: the trial stress is 123 Pa, the answer 1 MPa, and the map is
  // rounded to 1 nPa. With a tolerance taken from the trial stress alone (1.2e-10 Pa) the solve
  // never stopped and fell back to the trial stress (a jump of 1 MPa).
  for (const double c : {0.5, 2.5, 12.0, 37.0}) {
    LinearStep step{122.76, c, 0.0, 1e-9, {}};
    step.ref = (1e6 * (c - 1.0) + step.trial) / c;  // puts the fixed point at 1 MPa
    for (const double guess : {0.9e6, 1.0e6 + 0.3, 1.05e6, 122.76}) {
      step.calls.clear();
      const double s = consistent_sigma(step.trial, guess, step);
      EXPECT_NEAR(s, 1e6, 1e-6) << "c = " << c << ", guess = " << guess;
      ASSERT_FALSE(step.calls.empty());
      EXPECT_EQ(step.calls.back(), s) << "the last call must be step(answer)";
    }
  }
}

TEST(ConsistentSigma, AGuessWithinRoundingOfTheAnswerStillConverges) {
  // The guess is a few nPa from the answer, so the fixed-point step h0 is of the order of the
  // map's rounding; the first probe is then taken 1e-9 of the scale away (5 mPa here), where the
  // secant slope is the map's and not its rounding.
  LinearStep step{5e6, 3.0, 0.0, 1e-9, {}};
  step.ref = (2e6 * 2.0 + step.trial) / 3.0;  // fixed point 2 MPa
  const double guess = step.root() + 3e-9;
  const double s = consistent_sigma(step.trial, guess, step);
  EXPECT_NEAR(s, step.root(), 1e-5);
  EXPECT_EQ(step.calls.back(), s);
}

TEST(ConsistentSigma, ExpandingMapAndUnroundedMapsAreSolvedToTheTolerance) {
  // c < 1 (fixed-point iteration would converge too) and c > 1 (it would diverge), no rounding.
  for (const double c : {0.2, 0.9, 1.7, 60.0}) {
    LinearStep step{3e6, c, 2.5e6, 0.0, {}};
    const double s = consistent_sigma(step.trial, 2.9e6, step);
    EXPECT_NEAR(s, step.root(), 1e-12 * 3e6 * 4.0) << "c = " << c;
    EXPECT_EQ(step.calls.back(), s);
  }
}

TEST(ConsistentSigma, AGuessThatIsTheAnswerCostsOneCall) {
  LinearStep step{1e6, 2.0, 0.0, 0.0, {}};
  step.ref = (4e6 + step.trial) / 2.0;  // fixed point 4 MPa
  const double s = consistent_sigma(step.trial, 4e6, step);
  EXPECT_EQ(s, 4e6);
  EXPECT_EQ(step.calls.size(), 1u);
}

TEST(ConsistentSigma, AMapWithNoFixedPointFallsBackToTheTrialStress) {
  // step(s) = s + 1 MPa has no fixed point: the documented fallback is the trial stress, and the
  // last call is step(trial).
  std::vector<double> calls;
  auto step = [&calls](double s) {
    calls.push_back(s);
    return s + 1e6;
  };
  const double s = consistent_sigma(2e6, 2e6, step);
  EXPECT_EQ(s, 2e6);
  EXPECT_EQ(calls.back(), 2e6);
}
