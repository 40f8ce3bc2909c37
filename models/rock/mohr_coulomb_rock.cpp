// mohr_coulomb_rock: the Mohr-Coulomb model of Itasca's FLAC/UDEC zones (Itasca, FLAC
// Constitutive Models manual, "Mohr-Coulomb model": incremental elastic law, composite yield
// criterion f_s = s1 - s3 N_phi + 2c sqrt(N_phi), f_t = s_t - s3, non-associated shear flow with
// g_s = s1 - s3 N_psi, associated tension flow g_t = -s3, and the plastic corrections written in
// principal stresses s1 <= s2 <= s3, tension positive, with the zz stress as the third principal
// stress of plane strain). The choice between shear and tension return uses FLAC's function
// h = s3 - s_t + alpha_P (s1 - s_P) that bisects the corner of the two yield surfaces.
//
// Beyond the manual's single-surface corrections, two cases are treated so that the returned
// stress is always admissible (f_s >= 0, s3 <= s_t): tension corrections on two or three principal
// stresses at once (consistency on each active cut-off, as in FLAC3D's mohr model), and a
// corner return (shear and tension active together) when a single-surface correction leaves the
// other criterion violated. If reordering of the principal stresses after a correction leaves the
// state outside, the correction is repeated from the corrected state (at most a few passes).
#include "models/rock/mohr_coulomb_rock.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace rockdem {

std::vector<Param<MohrCoulombRock::Params>> MohrCoulombRock::Params::spec() {
  using P = Params;
  return {
      real("density", &P::density, Dimension::density, "mass density").positive(),
      real("bulk", &P::bulk, Dimension::stress, "bulk modulus K").positive(),
      real("shear", &P::shear, Dimension::stress, "shear modulus G").positive(),
      real("friction", &P::friction, Dimension::angle, "friction angle phi").min(0.0).max(M_PI / 2, true),
      real("cohesion", &P::cohesion, Dimension::stress, "cohesion c").non_negative(),
      real("dilation", &P::dilation, Dimension::angle, "dilation angle psi (<= friction)")
          .min(0.0)
          .max(M_PI / 2, true)
          .def(0.0),
      real("tension", &P::tension, Dimension::stress, "tensile strength (capped at c/tan(phi))")
          .non_negative()
          .def(0.0),
  };
}

void MohrCoulombRock::Params::validate() const {
  if (dilation > friction)
    throw InputError(std::string("rock material '") + MohrCoulombRock::name + "': dilation angle (" +
                     format_quantity(dilation, Dimension::angle) + ") must not exceed the friction angle (" +
                     format_quantity(friction, Dimension::angle) + ")");
}

double MohrCoulombRock::tension_cutoff(const Params& p) {
  if (p.friction > 0.0) return std::min(p.tension, p.cohesion / std::tan(p.friction));
  return p.cohesion == 0.0 ? 0.0 : p.tension;
}

double MohrCoulombRock::shear_yield(const Params& p, double s1, double s3) {
  const double sf = std::sin(p.friction);
  const double nphi = (1.0 + sf) / (1.0 - sf);
  return s1 - s3 * nphi + 2.0 * p.cohesion * std::sqrt(nphi);
}

void MohrCoulombRock::update(const Params& p, State& st, const Voigt3& de, Voigt3& sigma, double& szz) {
  if (st.flags & shear_now) st.flags |= shear_past;
  if (st.flags & tension_now) st.flags |= tension_past;
  st.flags &= ~(shear_now | tension_now);

  const double a1 = p.bulk + 4.0 * p.shear / 3.0, a2 = p.bulk - 2.0 * p.shear / 3.0;
  // Elastic trial.
  sigma[0] += a1 * de[0] + a2 * de[1];
  sigma[1] += a2 * de[0] + a1 * de[1];
  sigma[2] += p.shear * de[2];
  szz += a2 * (de[0] + de[1]);

  const double sphi = std::sin(p.friction), spsi = std::sin(p.dilation);
  const double nphi = (1.0 + sphi) / (1.0 - sphi), npsi = (1.0 + spsi) / (1.0 - spsi);
  const double csn = 2.0 * p.cohesion * std::sqrt(nphi);
  const double st_cut = tension_cutoff(p);

  // In-plane principal stresses and direction (kept fixed through the correction).
  const double centre = 0.5 * (sigma[0] + sigma[1]);
  const double half = 0.5 * (sigma[0] - sigma[1]);
  const double radius = std::hypot(half, sigma[2]);
  std::array<double, 3> ps{centre + radius, centre - radius, szz};  // a, b, zz

  const double scale = std::max({std::abs(ps[0]), std::abs(ps[1]), std::abs(ps[2]), p.cohesion, st_cut});
  const double tol = 1e-12 * scale;
  auto admissible = [&](double s1, double s3) { return s1 - s3 * nphi + csn >= -tol && s3 <= st_cut + tol; };
  {
    const auto [lo, hi] = std::minmax_element(ps.begin(), ps.end());
    if (admissible(*lo, *hi)) return;  // elastic
  }

  // Shear return direction D dg_s/dsigma in (s1, s2, s3) and its normalising denominator.
  const double ra = a1 - a2 * npsi, rb = a2 - a1 * npsi, r2 = a2 * (1.0 - npsi);
  const double rd = ra - rb * nphi;
  const double alpha_p = std::sqrt(1.0 + nphi * nphi) + nphi;
  const double sigma_p = st_cut * nphi - csn;  // s1 at the corner of the two surfaces
  auto add_shear_strain = [&](double lam) {
    // FLAC's shear-strain increment measure from the principal plastic strains (lam, 0, -lam N_psi).
    const double e1 = lam, e3 = -lam * npsi, em = (e1 + e3) / 3.0;
    st.plastic_shear += std::sqrt(0.5 * ((e1 - em) * (e1 - em) + em * em + (e3 - em) * (e3 - em)));
  };

  for (int pass = 0; pass < 4; ++pass) {
    std::array<int, 3> o{0, 1, 2};
    std::sort(o.begin(), o.end(), [&](int i, int j) { return ps[i] < ps[j]; });
    double s1 = ps[o[0]], s2 = ps[o[1]], s3 = ps[o[2]];
    const double fs = s1 - s3 * nphi + csn;
    const double ft = st_cut - s3;
    if (fs >= -tol && ft >= -tol) break;
    const double h = s3 - st_cut + alpha_p * (s1 - sigma_p);
    if (fs < 0.0 && h <= 0.0) {  // shear correction
      const double lam = fs / rd;
      double n1 = s1 - lam * ra, n2 = s2 - lam * r2, n3 = s3 - lam * rb;
      st.flags |= shear_now;
      if (n3 > st_cut + tol) {
        // Landed beyond the tension cut-off: corner return, both surfaces active.
        // s = s^I - ls*(ra, r2, rb) - lt*(-a2, -a2, -a1) with f_s(s) = 0 and s3 = s_t.
        const double m11 = ra - rb * nphi, m12 = -a2 + a1 * nphi;
        const double m21 = rb, m22 = -a1;
        const double det = m11 * m22 - m12 * m21;
        const double ls = (fs * m22 - m12 * (s3 - st_cut)) / det;
        const double lt = (m11 * (s3 - st_cut) - m21 * fs) / det;
        n1 = sigma_p;
        n3 = st_cut;
        n2 = std::clamp(s2 - ls * r2 + lt * a2, n1, n3);
        st.flags |= tension_now;
        st.plastic_tension += std::abs(lt);
        add_shear_strain(ls);
      } else {
        add_shear_strain(lam);
      }
      s1 = n1;
      s2 = n2;
      s3 = n3;
    } else {  // tension correction, on as many principal stresses as exceed the cut-off
      st.flags |= tension_now;
      const double f3 = s3 - st_cut, f2 = s2 - st_cut;
      if (s2 - f3 * a2 / a1 <= st_cut) {
        s1 -= f3 * a2 / a1;
        s2 -= f3 * a2 / a1;
        st.plastic_tension += f3 / a1;
      } else {
        const double l23 = (f2 + f3) / (a1 + a2);  // sum of the two multipliers
        s1 -= l23 * a2;
        s2 = st_cut;
        st.plastic_tension += l23;
        if (s1 > st_cut) s1 = st_cut;  // all three at the cut-off (hydrostatic tension limit)
      }
      s3 = st_cut;
    }
    ps[o[0]] = s1;
    ps[o[1]] = s2;
    ps[o[2]] = s3;
  }

  // Back to x, y with the unchanged in-plane principal directions.
  const double c2 = radius > 0.0 ? half / radius : 1.0, s2t = radius > 0.0 ? sigma[2] / radius : 0.0;
  const double nc = 0.5 * (ps[0] + ps[1]), nr = 0.5 * (ps[0] - ps[1]);
  sigma[0] = nc + nr * c2;
  sigma[1] = nc - nr * c2;
  sigma[2] = nr * s2t;
  szz = ps[2];
}

}  // namespace rockdem

ROCKDEM_REGISTER_ROCK_MATERIAL(rockdem::MohrCoulombRock,
                               "elastic, perfectly plastic Mohr-Coulomb rock with tension cut-off and "
                               "non-associated flow (plane strain)",
                               "Itasca FLAC Constitutive Models manual, Mohr-Coulomb model (principal-stress "
                               "plastic corrections); Vermeer & de Borst (1984) for non-associated flow")
