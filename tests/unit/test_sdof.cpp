// The exact piecewise-linear SDOF recurrence (framework/seismic/sdof.hpp) against closed forms
// it must reproduce at any time step (free vibration, step and ramp loads), and the El Centro
// check values of cases/data/ground_motions/README.md.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/seismic/ground_motion.hpp"
#include "framework/seismic/sdof.hpp"

using namespace rockdem;
using namespace rockdem::seismic;

namespace {

struct Modal {
  double wn, wd, z;
  explicit Modal(const SdofOscillator& o)
      : wn(2.0 * std::numbers::pi / o.period), wd(wn * std::sqrt(1.0 - o.damping * o.damping)), z(o.damping) {}
  // Homogeneous solution with u(0) = u0, u'(0) = v0 (Chopra eq. 2.2.4).
  double free(double t, double u0, double v0) const {
    return std::exp(-z * wn * t) * (u0 * std::cos(wd * t) + (v0 + z * wn * u0) / wd * std::sin(wd * t));
  }
  double free_rate(double t, double u0, double v0) const {
    const double h = 1e-7;  // central difference of the closed form; error ~1e-14 here
    return (free(t + h, u0, v0) - free(t - h, u0, v0)) / (2.0 * h);
  }
};

}  // namespace

TEST(Sdof, FreeVibrationMatchesClosedFormAtAnyStep) {
  for (double dt : {0.001, 0.05, 0.3}) {
    for (double zeta : {0.0, 0.05, 0.4}) {
      const SdofOscillator osc{0.7, zeta};
      const Modal m(osc);
      const std::vector<double> ag(200, 0.0);
      const auto r = sdof_response(ag, dt, osc, 0.01, -0.05);
      for (std::size_t i = 0; i < ag.size(); ++i) {
        const double t = dt * static_cast<double>(i);
        EXPECT_NEAR(r.u[i], m.free(t, 0.01, -0.05), 1e-12) << "dt " << dt << " zeta " << zeta << " step " << i;
        EXPECT_NEAR(r.v[i], m.free_rate(t, 0.01, -0.05), 1e-7) << "dt " << dt << " zeta " << zeta << " step " << i;
      }
    }
  }
}

TEST(Sdof, StepLoadMatchesClosedForm) {
  // u'' + 2 zeta wn u' + wn^2 u = -a0 from rest: u = -(a0/wn^2) [1 - e^{-zeta wn t}(cos wd t +
  // zeta/sqrt(1-zeta^2) sin wd t)] (Chopra eq. 4.3.2).
  const SdofOscillator osc{1.3, 0.1};
  const Modal m(osc);
  const double a0 = 2.5, dt = 0.1;
  const std::vector<double> ag(150, a0);
  const auto r = sdof_response(ag, dt, osc);
  for (std::size_t i = 0; i < ag.size(); ++i) {
    const double t = dt * static_cast<double>(i);
    const double u = -a0 / (m.wn * m.wn) *
                     (1.0 - std::exp(-m.z * m.wn * t) *
                                (std::cos(m.wd * t) + m.z / std::sqrt(1.0 - m.z * m.z) * std::sin(m.wd * t)));
    EXPECT_NEAR(r.u[i], u, 1e-13) << "step " << i;
  }
  // Static limit after the transient has died away.
  EXPECT_NEAR(r.u.back(), -a0 / (m.wn * m.wn), 1e-3 * a0 / (m.wn * m.wn));
}

TEST(Sdof, RampLoadIsExactWithCoarseSteps) {
  // ag = c t: particular solution u_p = -(c/wn^2)(t - 2 zeta / wn) plus the free vibration that
  // starts the motion from rest. A ramp exercises the coefficients of p_{i+1} (C, D, C', D').
  const SdofOscillator osc{0.5, 0.05};
  const Modal m(osc);
  const double c = 0.8, dt = 0.17;  // a third of the period: only an exact scheme stays exact
  std::vector<double> ag(60);
  for (std::size_t i = 0; i < ag.size(); ++i) ag[i] = c * dt * static_cast<double>(i);
  const auto r = sdof_response(ag, dt, osc);
  const double w2 = m.wn * m.wn;
  const double up0 = 2.0 * m.z * c / (w2 * m.wn), vp = -c / w2;
  for (std::size_t i = 0; i < ag.size(); ++i) {
    const double t = dt * static_cast<double>(i);
    const double u = -(c / w2) * (t - 2.0 * m.z / m.wn) + m.free(t, -up0, -vp);
    const double v = vp + m.free_rate(t, -up0, -vp);
    EXPECT_NEAR(r.u[i], u, 1e-12) << "step " << i;
    EXPECT_NEAR(r.v[i], v, 1e-8) << "step " << i;
  }
}

TEST(Sdof, ElCentroCheckValues) {
  // The reference values (cases/data/ground_motions/README.md) take g = 9.81 m/s^2.
  RecordLayout layout;
  layout.unit = parse_acceleration_unit("9.81 m/s^2");
  const auto g = load_ground_motion(ROCKDEM_SOURCE_DIR "/cases/data/ground_motions/elcentro1940_ns_acc_g.csv", layout);
  ASSERT_EQ(g.acc.size(), 1560u);
  ASSERT_NEAR(g.dt, 0.02, 1e-12);
  const struct {
    double period, peak;
  } checks[] = {{0.5, 0.067940}, {1.0, 0.151592}, {2.0, 0.189675}};
  for (const auto& c : checks) {
    const double u = sdof_peak_displacement(g.acc, g.dt, SdofOscillator{c.period, 0.02});
    EXPECT_NEAR(u / c.peak, 1.0, 1e-5) << "Tn = " << c.period << " s: " << u << " m";
  }
  // The response is linear in the record: with standard gravity every peak drops by 9.80665/9.81.
  RecordLayout standard;
  standard.unit = parse_acceleration_unit("g");
  const auto gs = load_ground_motion(ROCKDEM_SOURCE_DIR "/cases/data/ground_motions/elcentro1940_ns_acc_g.csv", standard);
  const double u = sdof_peak_displacement(gs.acc, gs.dt, SdofOscillator{0.5, 0.02});
  EXPECT_NEAR(u / 0.067940, 9.80665 / 9.81, 1e-5);
}

TEST(Sdof, RejectsInvalidOscillators) {
  const std::vector<double> ag(10, 0.0);
  EXPECT_THROW(sdof_response(ag, 0.01, SdofOscillator{0.0, 0.05}), InputError);
  EXPECT_THROW(sdof_response(ag, 0.01, SdofOscillator{1.0, 1.0}), InputError);
  EXPECT_THROW(sdof_response(ag, 0.01, SdofOscillator{1.0, -0.1}), InputError);
  EXPECT_THROW(sdof_response(ag, 0.0, SdofOscillator{1.0, 0.05}), InputError);
}
