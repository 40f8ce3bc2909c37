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
// Every other form too: a form left to the library (std::stable_sort uses the nothrow new) would
// allocate with the library's new and be freed here with free(), which AddressSanitizer reports
// as an alloc-dealloc mismatch.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
namespace {
void* aligned(std::size_t n, std::align_val_t a) noexcept {
  ++g_allocations;
  const auto al = static_cast<std::size_t>(a);
  // aligned_alloc needs a size that is a multiple of the alignment.
  return std::aligned_alloc(al, ((n ? n : 1) + al - 1) / al * al);
}
}  // namespace
void* operator new(std::size_t n, std::align_val_t a) {
  if (void* p = aligned(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) {
  if (void* p = aligned(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept { return aligned(n, a); }
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept { return aligned(n, a); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

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
