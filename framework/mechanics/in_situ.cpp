#include "framework/mechanics/in_situ.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {
namespace {

// The increment x along one direction (normal closure or shear) that brings a contact's stress
// from `now` to `target`; `stress_after(x)` is the stress after the increment x from the
// contact's present state. The stress grows with the increment in the direction taken, so the
// root is bracketed by doubling from the elastic estimate gap/k0 and then bisected. A target the
// law cannot reach (a shear stress beyond the joint's strength) gives the smallest increment at
// which the stress stops growing, the onset of slip, so that no spurious slip is added to the
// joint's history; `reached` is then false.
template <class StressAfter>
double solve_increment(double now, double target, double k0, StressAfter stress_after, bool& reached) {
  reached = true;
  const double gap = std::abs(target - now);
  if (gap <= 1e-12 * std::max(1.0, std::abs(target))) return 0.0;
  const double dir = target > now ? 1.0 : -1.0;
  auto excess = [&](double x) { return dir * (stress_after(dir * x) - target); };  // < 0 before the root
  double lo = 0.0, hi = gap / std::max(k0, 1e-300);
  double best = excess(hi);
  int doublings = 0;
  while (best < 0.0) {
    if (++doublings > 60) break;
    const double next = excess(2.0 * hi);
    if (next <= best + 1e-12 * std::max(1.0, std::abs(target))) {  // no longer growing: at strength
      reached = false;
      break;
    }
    lo = hi;
    hi *= 2.0;
    best = next;
  }
  if (best < 0.0) {
    // Unreachable: the smallest increment that gives (nearly) the largest stress.
    reached = false;
    const double top = best;
    lo = 0.0;
    for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (excess(mid) < top - 1e-9 * std::max(1.0, std::abs(target)) ? lo : hi) = mid;
    }
    return dir * hi;
  }
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) < 0.0 ? lo : hi) = mid;
  }
  return dir * hi;
}

void initialise_zones(Model& m, const StressField& field, InSituReport& rep) {
  for (auto& z : m.zones) {
    const Vec2 xc = (m.gp[z.n[0]].x + m.gp[z.n[1]].x + m.gp[z.n[2]].x) / 3.0;
    z.stress = field.at(xc);
    const RockMaterialBase& mat = *m.materials[z.material];
    const double kb = mat.bulk_modulus(), g = mat.shear_modulus();
    const double nu = (3.0 * kb - 2.0 * g) / (2.0 * (3.0 * kb + g));
    z.szz = nu * (z.stress[0] + z.stress[1]);
    ++rep.zones;
  }
}

}  // namespace

double preload_contact(Contact& c, std::byte* state, const JointModel& model, double sn, double tau, bool& at_strength) {
  JointKinematics k;
  k.length = std::max(c.length, 1e-12);
  k.dt = 0.0;  // pseudo-static: rate-dependent effects see no time pass
  // A trial from the contact's present state, which it leaves as it is.
  auto after = [&](double du_n, double du_s) {
    std::pair<JointStateBlock, JointResponse> out{JointStateBlock{}, JointResponse{}};
    std::memcpy(out.first.bytes.data(), state, model.state_size());
    k.du_n = du_n;
    k.du_s = du_s;
    model.update(out.first, k, out.second);
    return out;
  };
  auto keep = [&](const std::pair<JointStateBlock, JointResponse>& trial) {
    std::memcpy(state, trial.first.bytes.data(), model.state_size());
    return trial.second;
  };
  JointResponse r = after(0.0, 0.0).second;
  at_strength = false;
  // A shear increment may dilate and so move the normal stress: alternate the two a few times.
  for (int pass = 0; pass < 4; ++pass) {
    bool reached = true;
    const double dn = solve_increment(r.sigma_n, sn, model.initial_kn(),
                                      [&](double x) { return after(-x, 0.0).second.sigma_n; }, reached);
    r = keep(after(-dn, 0.0));
    const double ds = solve_increment(r.tau, tau, model.initial_ks(),
                                      [&](double x) { return after(0.0, x).second.tau; }, reached);
    r = keep(after(0.0, ds));
    at_strength = !reached;
    if (std::abs(r.sigma_n - sn) <= 1e-9 * std::max(1.0, sn) || at_strength) break;
  }
  c.response = r;
  return std::max(std::abs(r.sigma_n - sn), at_strength ? 0.0 : std::abs(r.tau - tau));
}

InSituReport initialise_in_situ(Model& m, const StressField& field, const DetectionSettings& detection) {
  InSituReport rep;
  initialise_zones(m, field, rep);
  detect_contacts(m, detection);
  // Blocks that share an edge touch to round-off; those a visible gap apart are left open.
  const double touch = 1e-9 * std::max(1.0, detection.distance * 1e3);
  for (std::size_t i = 0; i < m.contacts.items.size(); ++i) {
    Contact& c = m.contacts.items[i];
    if (c.overlap < -touch) continue;
    const Vec2 n = c.normal, t(n.y(), -n.x());
    const Voigt3 s = field.at(m.gp[c.point].x);
    const Vec2 sn_vec(s[0] * n.x() + s[2] * n.y(), s[2] * n.x() + s[1] * n.y());  // sigma . n
    const double sn = std::max(0.0, -n.dot(sn_vec));  // joints carry no tension
    const double tau = sn > 0.0 ? t.dot(sn_vec) : 0.0;
    // The overlap at the start is round-off of blocks that share edges, not a closure to feed.
    c.pretouch_gap = 0.0;
    c.pending_closure = 0.0;
    c.fresh = false;
    bool at_strength = false;
    const double error = preload_contact(c, m.contacts.states.at(i), *m.contacts.models[c.joint], sn, tau, at_strength);
    rep.worst_error = std::max(rep.worst_error, error);
    if (at_strength) ++rep.at_strength;
    ++rep.contacts;
  }
  update_contact_lengths(m, detection);
  return rep;
}

}  // namespace rockdem
