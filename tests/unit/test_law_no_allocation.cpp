// The per-contact law update and the element driver's increment must not allocate: counted by
// replacing the global allocation functions for this test binary (counting only; they still
// allocate with malloc).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>

#include "tests/unit/joint_law_test_util.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace rockdem;
using namespace rockdem::testutil;

TEST(NoAllocation, LawUpdatesAndDriverIncrementsDoNotAllocate) {
  {  // the counter is live in this binary
    const long at_start = g_allocations.load();
    auto probe = std::make_unique<double>(1.0);
    EXPECT_GT(g_allocations.load() - at_start, 0);
  }
  const std::vector<std::pair<const char*, RawValues>> laws = {
      {"mohr_coulomb", mc_report({{"dilation", "udec_legacy"}, {"critical_shear_disp", "5 mm"}})},
      {"barton_bandis", bb_report({{"normal_closure", "bandis"}, {"ucs", "200 MPa"}})},
      {"continuously_yielding", cy_report({{"dilation", "reversible"}})}};
  for (const auto& [law, params] : laws) {
    auto m = model(law, params, {EffectSpec{"strength_reduction", values({{"factor", "1.2"}}), "t"},
                                 EffectSpec{"strength_reduction", values({{"enabled", "false"}}), "t"}});
    JointStateBlock s;
    m->init(s);
    JointResponse r;
    JointKinematics k;
    k.du_n = -2e6 / m->initial_kn();
    const long before = g_allocations.load();
    m->update(s, k, r);
    k.du_n = 0.0;
    for (int i = 0; i < 10000; ++i) {
      k.du_s = (i / 1000) % 2 ? -1e-5 : 1e-5;
      k.du_n = i == 5000 ? 1e-3 : (i == 5100 ? -1e-3 : 0.0);  // separation and re-contact
      m->update(s, k, r);
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << law;

    ElementDriver d(*m);
    const ElementStage st = cnl(3e6, ShearPath::cycles(0.01, 1, 1e-4));
    d.begin_stage(st);
    const long before_driver = g_allocations.load();
    for (int i = 0; i < 4000; ++i) d.step(st, (i / 1000) % 2 ? -1e-5 : 1e-5, 0.01);
    EXPECT_EQ(g_allocations.load() - before_driver, 0) << law;
  }
}
