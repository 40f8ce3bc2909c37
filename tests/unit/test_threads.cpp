// Threads inside one process (framework/core/threads.hpp, EngineSettings::threads): the loops
// visit every item once, stop with the error of the lowest item whatever the thread count, and an
// engine run gives the same state, to the bit, on one thread and on several.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "framework/boundary/fixed_condition.hpp"
#include "framework/core/threads.hpp"
#include "framework/mechanics/engine.hpp"
#include "framework/mechanics/zones.hpp"
#include "framework/plugin_api/joint_law.hpp"
#include "models/rock/elastic.hpp"

using namespace rockdem;

TEST(Threads, EveryItemOnceOnAnyThreadCount) {
  for (int threads : {1, 2, 3, 7}) {
    std::vector<std::atomic<int>> seen(5000);
    threaded_for(threads, 100, 5000, [&](std::ptrdiff_t i) { seen[static_cast<std::size_t>(i)]++; });
    for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), i < 100 ? 0 : 1) << threads << " threads, item " << i;
    std::vector<std::atomic<int>> chunks(40);
    threaded_chunks(threads, 40, [&](std::ptrdiff_t c) { chunks[static_cast<std::size_t>(c)]++; });
    for (const auto& c : chunks) ASSERT_EQ(c.load(), 1);
  }
}

TEST(Threads, ALoopInsideALoopRunsOnItsThread) {
  // Not done by the engine today; it must neither hang nor lose items.
  std::vector<std::atomic<int>> seen(600 * 300);
  threaded_for(2, 0, 600, [&](std::ptrdiff_t i) {
    threaded_for(3, 0, 300, [&](std::ptrdiff_t j) { seen[static_cast<std::size_t>(i * 300 + j)]++; });
  });
  for (const auto& s : seen) ASSERT_EQ(s.load(), 1);
}

TEST(Threads, TheErrorOfTheLowestItemWhateverTheThreadCount) {
  for (int threads : {1, 2, 4}) {
    try {
      threaded_for(threads, 0, 10000, [](std::ptrdiff_t i) {
        if (i == 7000 || i == 2500 || i == 9999) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "no error on " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 2500") << threads << " threads";
    }
    try {
      threaded_chunks(threads, 50, [](std::ptrdiff_t c) {
        if (c == 31 || c == 12) throw std::runtime_error("chunk " + std::to_string(c));
      });
      FAIL() << "no error on " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "chunk 12") << threads << " threads";
    }
  }
}

TEST(Threads, TheLargestValueAsOneThreadTakesIt) {
  std::vector<double> v(3000);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(0.37 * static_cast<double>(i)) * static_cast<double>(i % 97);
  v[1234] = std::numeric_limits<double>::quiet_NaN();
  double one = 0.0;
  for (double x : v) one = std::max(one, x);
  for (int threads : {1, 2, 3})
    EXPECT_EQ(threaded_max(threads, 0, 3000, [&](std::ptrdiff_t i) { return v[static_cast<std::size_t>(i)]; }), one);
  EXPECT_EQ(threaded_max(2, 0, 3000, [](std::ptrdiff_t) { return -1.0; }), 0.0);  // the largest of 0 and the values
}

namespace {

RawValues values(std::initializer_list<std::pair<const char*, const char*>> kv) {
  RawValues v;
  for (const auto& [k, x] : kv) v[k] = RawValue{std::string(x), "test"};
  return v;
}

// A row of deformable blocks on a rigid base under a stack of rigid bricks that drop a little
// onto it: more zones, gridpoints, rigid blocks and contacts than a loop needs before it is split
// over threads (kThreadedLoopMin), two joint laws (one dilating), contacts made and lost.
void build(Model& m) {
  m.gravity = Vec2(0.0, -9.81);
  m.contacts.models.push_back(make_joint_model("coulomb_slip", values({{"kn", "10 GPa/m"}, {"ks", "5 GPa/m"}, {"friction", "30 deg"}}), {}, "test"));
  m.contacts.models.push_back(make_joint_model(
      "mohr_coulomb", values({{"kn", "20 GPa/m"}, {"ks", "10 GPa/m"}, {"friction", "35 deg"}, {"dilation_angle", "5 deg"}, {"dilation", "reversible"}}), {}, "test"));
  m.contacts.model_names = {"bricks", "rock"};
  m.contacts.assignments.push_back({1, 1, 1});
  m.contacts.assignments.push_back({-1, -1, 0});
  m.materials.push_back(std::make_unique<RockMaterialAdapter<ElasticRock>>(ElasticRock::Params{2500.0, 2e9, 1.5e9}));
  add_rigid_block(m, Polygon{Vec2(-0.1, -0.5), Vec2(8.1, -0.5), Vec2(8.1, 0), Vec2(-0.1, 0)}, 2500.0, "base", 0);
  for (int i = 0; i < 8; ++i)
    add_deformable_block(m, mesh_rectangle(i * 1.0 + 0.001, 1e-4, 0.998, 0.5, 8, 4), 0, "rock" + std::to_string(i), 1);
  for (int row = 0; row < 14; ++row)
    for (int k = 0; k < 20; ++k) {
      const double x0 = 0.02 + k * 0.4 + (row % 2) * 0.2 - (row % 2 && k == 19 ? 0.2 : 0.0);
      const double y0 = 0.5 + 1e-3 + row * 0.1003;
      add_rigid_block(m, Polygon{Vec2(x0, y0), Vec2(x0 + 0.38, y0), Vec2(x0 + 0.38, y0 + 0.1), Vec2(x0, y0 + 0.1)}, 2500.0,
                      "brick" + std::to_string(row) + "_" + std::to_string(k), 0);
    }
}

// Every evolving value, as bytes.
std::vector<unsigned char> state_bytes(const Model& m) {
  std::vector<unsigned char> out;
  auto put = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    out.insert(out.end(), b, b + n);
  };
  for (const GridPoint& g : m.gp) {
    put(g.x.data(), 2 * sizeof(double));
    put(g.v.data(), 2 * sizeof(double));
    put(g.f.data(), 2 * sizeof(double));
    put(&g.stiffness, sizeof(double));
  }
  for (const Zone& z : m.zones) {
    put(z.stress.data(), 3 * sizeof(double));
    put(z.strain.data(), 3 * sizeof(double));
    put(&z.szz, sizeof(double));
    put(z.material_state.data(), z.material_state.size());
  }
  for (const Block& b : m.blocks) {
    put(b.xc.data(), 2 * sizeof(double));
    put(b.vc.data(), 2 * sizeof(double));
    put(&b.theta, sizeof(double));
    put(&b.omega, sizeof(double));
  }
  for (std::size_t i = 0; i < m.contacts.items.size(); ++i) {
    const Contact& c = m.contacts.items[i];
    put(&c.key, sizeof c.key);
    put(&c.length, sizeof(double));
    put(&c.overlap, sizeof(double));
    put(c.normal.data(), 2 * sizeof(double));
    put(&c.edge, sizeof c.edge);
    put(&c.s, sizeof(double));
    put(&c.response.sigma_n, sizeof(double));
    put(&c.response.tau, sizeof(double));
    put(m.contacts.states.at(i), m.contacts.states.stride());
  }
  return out;
}

struct Outcome {
  std::vector<unsigned char> state;
  std::vector<double> ratios, dts;
  std::size_t zones = 0, contacts = 0, rigid = 0;
};

// The model above and an engine stepping it on `threads` threads.
struct SteppedModel {
  explicit SteppedModel(int threads) : e(m, settings(threads)) { build(m); }
  static EngineSettings settings(int threads) {
    EngineSettings s;
    s.detection.distance = 2e-3;
    s.threads = threads;
    return s;
  }
  Model m;
  Engine e;
};

Outcome run(int threads) {
  SteppedModel setup(threads);
  Model& m = setup.m;
  Engine& e = setup.e;
  FaceSelection base;
  base.block = 0;
  base.points = m.blocks[0].boundary;
  e.add_condition(std::make_unique<FixedCondition>(base, true, true, true));
  Outcome r;
  e.begin_stage("drop", Damping{});
  for (int i = 0; i < 300; ++i) {
    e.step();
    r.ratios.push_back(e.unbalanced_ratio());
    r.dts.push_back(e.dt());
  }
  e.begin_stage("ring", Damping::rayleigh(0.05, 50.0));
  for (int i = 0; i < 200; ++i) {
    e.step();
    r.ratios.push_back(e.unbalanced_ratio());
    r.dts.push_back(e.dt());
  }
  r.state = state_bytes(m);
  r.zones = m.zones.size();
  r.contacts = m.contacts.items.size();
  for (const Block& b : m.blocks) r.rigid += b.rigid;
  return r;
}

}  // namespace

TEST(Threads, AnEngineRunIsTheSameToTheBitOnAnyThreadCount) {
  const Outcome one = run(1);
  // Large enough that every threaded loop is split: zones, gridpoints, rigid blocks, contacts.
  ASSERT_GE(one.zones, 2 * static_cast<std::size_t>(kThreadedLoopMin));
  ASSERT_GE(one.rigid, static_cast<std::size_t>(kThreadedLoopMin));
  ASSERT_GE(one.contacts, 2 * static_cast<std::size_t>(kThreadedLoopMin));
  std::printf("%zu zones, %zu rigid blocks, %zu contacts at the end\n", one.zones, one.rigid, one.contacts);
  for (int threads : {2, 3}) {
    const Outcome many = run(threads);
    EXPECT_EQ(many.ratios, one.ratios) << threads << " threads";
    EXPECT_EQ(many.dts, one.dts) << threads << " threads";
    ASSERT_EQ(many.state.size(), one.state.size()) << threads << " threads";
    EXPECT_TRUE(std::memcmp(many.state.data(), one.state.data(), one.state.size()) == 0) << threads << " threads";
  }
}

TEST(Threads, AnInvertedZoneStopsTheRunWithTheSameMessage) {
  // Zones of the first and of the last deformable block turned inside out by hand (on three
  // threads, different threads meet them): the first block's error on any count.
  std::vector<std::string> messages;
  for (int threads : {1, 3}) {
    SteppedModel setup(threads);
    Model& m = setup.m;
    Engine& e = setup.e;
    e.begin_stage("drop", Damping{});
    for (std::size_t iz : {std::size_t{5}, m.zones.size() - 5}) {
      const Zone& z = m.zones[iz];
      std::swap(m.gp[static_cast<std::size_t>(z.n[0])].x, m.gp[static_cast<std::size_t>(z.n[1])].x);
    }
    try {
      e.step();
      messages.push_back("no error");
    } catch (const InstabilityError& err) {
      messages.push_back(err.what());
    }
  }
  EXPECT_NE(messages[0].find("of block 'rock0' turned inside out"), std::string::npos) << messages[0];
  EXPECT_EQ(messages[1], messages[0]);
}
