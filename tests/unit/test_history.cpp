// History: values, units and descriptions read back with the plain HDF5 C API, incremental
// appends across chunk boundaries, and data surviving a process that dies without closing.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "framework/core/error.hpp"
#include "framework/io/history.hpp"

namespace fs = std::filesystem;
using rockdem::History;

namespace {

fs::path temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("rockdem_test_history_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

template <class T>
std::vector<T> read_1d(hid_t file, const std::string& name, hid_t type) {
  hid_t ds = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(ds, 0) << name;
  if (ds < 0) return {};
  hid_t space = H5Dget_space(ds);
  EXPECT_EQ(H5Sget_simple_extent_ndims(space), 1) << name;
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space, &n, nullptr);
  std::vector<T> v(n);
  if (n > 0) {
    EXPECT_GE(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  }
  H5Sclose(space);
  H5Dclose(ds);
  return v;
}

std::string read_string_attr(hid_t file, const std::string& obj, const std::string& name) {
  hid_t a = H5Aopen_by_name(file, obj.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
  EXPECT_GE(a, 0) << obj << "@" << name;
  if (a < 0) return {};
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  char* p = nullptr;
  EXPECT_GE(H5Aread(a, t, &p), 0);
  std::string s = p ? p : "";
  H5free_memory(p);
  H5Tclose(t);
  H5Aclose(a);
  return s;
}

}  // namespace

TEST(History, WritesValuesUnitsAndDescriptions) {
  const fs::path dir = temp_dir("basic");
  History h;
  const int ss = h.define("shear_stress", "Pa", "joint shear stress (loading-block reaction / joint length)");
  const int ux = h.define("shear_displacement", "m", "loading-block travel");
  EXPECT_EQ(ss, 0);
  EXPECT_EQ(ux, 1);
  EXPECT_EQ(h.id("shear_displacement"), 1);
  EXPECT_EQ(h.id("nope"), -1);
  for (int i = 0; i < 5; ++i) {
    const double vals[2] = {1.5e6 * i, 1e-3 * i};
    h.sample(0.01 * i, 100L * i, vals);
  }
  h.set(ux, 0.25);  // per-name API: shear_stress left unset -> NaN
  h.commit(1.0, 1000);
  ASSERT_EQ(h.sample_count(), 6u);

  const std::string path = (dir / "h.h5").string();
  h.write_hdf5(path);

  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const auto t = read_1d<double>(f, "/history/time", H5T_NATIVE_DOUBLE);
  const auto st = read_1d<long long>(f, "/history/step", H5T_NATIVE_LLONG);
  const auto tau = read_1d<double>(f, "/history/shear_stress", H5T_NATIVE_DOUBLE);
  const auto u = read_1d<double>(f, "/history/shear_displacement", H5T_NATIVE_DOUBLE);
  ASSERT_EQ(t.size(), 6u);
  ASSERT_EQ(st.size(), 6u);
  ASSERT_EQ(tau.size(), 6u);
  ASSERT_EQ(u.size(), 6u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(t[i], 0.01 * i);
    EXPECT_EQ(st[i], 100LL * i);
    EXPECT_EQ(tau[i], 1.5e6 * i);
    EXPECT_EQ(u[i], 1e-3 * i);
  }
  EXPECT_EQ(t[5], 1.0);
  EXPECT_EQ(st[5], 1000);
  EXPECT_TRUE(std::isnan(tau[5]));
  EXPECT_EQ(u[5], 0.25);
  EXPECT_EQ(read_string_attr(f, "/history/shear_stress", "unit"), "Pa");
  EXPECT_EQ(read_string_attr(f, "/history/shear_displacement", "unit"), "m");
  EXPECT_EQ(read_string_attr(f, "/history/time", "unit"), "s");
  EXPECT_EQ(read_string_attr(f, "/history/shear_stress", "description"),
            "joint shear stress (loading-block reaction / joint length)");
  H5Fclose(f);
  fs::remove_all(dir);
}

TEST(History, RejectsBadNamesAndLateDefinitions) {
  History h;
  EXPECT_THROW(h.define("a/b", "m"), rockdem::InputError);
  EXPECT_THROW(h.define("time", "s"), rockdem::InputError);
  EXPECT_THROW(h.define("", "s"), rockdem::InputError);
  h.define("a", "m");
  EXPECT_THROW(h.define("a", "m"), rockdem::InputError);
  const double one[1] = {1.0};
  h.sample(0.0, 0, one);
  EXPECT_THROW(h.define("b", "m"), std::logic_error);
  const double two[2] = {1.0, 2.0};
  EXPECT_THROW(h.sample(1.0, 1, two), std::logic_error);
}

TEST(History, IncrementalAppendsAcrossChunks) {
  const fs::path dir = temp_dir("incr");
  const std::string path = (dir / "h.h5").string();
  History h;
  h.define("x", "m", "position");
  h.open(path);
  h.set_flush_policy(7, 1e9);  // flush every 7 samples: exercises many partial appends
  const int n = 3000;          // > 2 chunks of 1024
  for (int i = 0; i < n; ++i) {
    const double v[1] = {std::sin(0.001 * i)};
    h.sample(i * 1e-4, i, v);
  }
  h.close();
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const auto x = read_1d<double>(f, "/history/x", H5T_NATIVE_DOUBLE);
  const auto st = read_1d<long long>(f, "/history/step", H5T_NATIVE_LLONG);
  ASSERT_EQ(x.size(), static_cast<std::size_t>(n));
  ASSERT_EQ(st.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    ASSERT_EQ(x[static_cast<std::size_t>(i)], std::sin(0.001 * i)) << i;
    ASSERT_EQ(st[static_cast<std::size_t>(i)], i) << i;
  }
  H5Fclose(f);
  fs::remove_all(dir);
}

// A run that dies (here: _exit without destructors) keeps everything up to its last flush.
TEST(History, SurvivesAProcessThatDiesWithoutClosing) {
  const fs::path dir = temp_dir("crash");
  const std::string path = (dir / "h.h5").string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    History h;
    h.define("y", "Pa");
    h.open(path);
    h.set_flush_policy(10, 1e9);
    for (int i = 0; i < 25; ++i) {
      const double v[1] = {2.0 * i};
      h.sample(i, i, v);
    }
    _exit(0);  // samples 20..24 were never flushed
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0) << "history file unreadable after the writer died";
  const auto y = read_1d<double>(f, "/history/y", H5T_NATIVE_DOUBLE);
  ASSERT_EQ(y.size(), 20u);
  for (std::size_t i = 0; i < y.size(); ++i) EXPECT_EQ(y[i], 2.0 * static_cast<double>(i));
  H5Fclose(f);
  fs::remove_all(dir);
}

// Users read the history of a run that is still going (plot_history.py): the writer must not
// hold HDF5's file lock, which would make every reader fail until the run ends.
TEST(History, ReadableByAnotherProcessWhileTheRunWrites) {
  const fs::path dir = temp_dir("live");
  const std::string path = (dir / "h.h5").string();
  int ready[2], done[2];
  ASSERT_EQ(pipe(ready), 0);
  ASSERT_EQ(pipe(done), 0);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {  // the "run": writes, flushes, and keeps the file open until told to stop
    History h;
    h.define("z", "m");
    h.open(path);
    for (int i = 0; i < 12; ++i) {
      const double v[1] = {0.5 * i};
      h.sample(i, i, v);
    }
    h.flush();
    char c = 'r';
    if (write(ready[1], &c, 1) != 1) _exit(2);
    if (read(done[0], &c, 1) != 1) _exit(3);
    _exit(0);
  }
  char c = 0;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);  // default (locking) access
  EXPECT_GE(f, 0) << "the history of a running job cannot be opened";
  if (f >= 0) {
    const auto z = read_1d<double>(f, "/history/z", H5T_NATIVE_DOUBLE);
    EXPECT_EQ(z.size(), 12u);
    if (!z.empty()) {
      EXPECT_EQ(z.back(), 5.5);
    }
    H5Fclose(f);
  }
  c = 'd';
  EXPECT_EQ(write(done[1], &c, 1), 1);
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  for (int fd : {ready[0], ready[1], done[0], done[1]}) close(fd);
  fs::remove_all(dir);
}
