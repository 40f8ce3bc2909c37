#include "framework/io/history.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "framework/core/error.hpp"
#include "framework/io/hdf5_util.hpp"

namespace rockdem {

namespace {
constexpr hsize_t kChunk = 1024;  // samples per chunk: 8 KiB per series, small files stay small

h5::Handle create_extendible(hid_t group, const std::string& name, hid_t type, const std::string& file) {
  const hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {kChunk};
  h5::Handle space(h5::check(H5Screate_simple(1, dims, maxdims), "dataspace"), H5Sclose);
  h5::Handle plist(h5::check(H5Pcreate(H5P_DATASET_CREATE), "dataset properties"), H5Pclose);
  h5::check_status(H5Pset_chunk(plist, 1, chunk), "chunking");
  return {h5::check(H5Dcreate2(group, name.c_str(), type, space, H5P_DEFAULT, plist, H5P_DEFAULT),
                    "cannot create dataset /history/" + name + " in " + file),
          H5Dclose};
}

// Appends data[from, to) to a one-dimensional extendible dataset that holds `from` values.
template <class T>
void append(hid_t ds, const std::vector<T>& data, std::size_t from, std::size_t to, const std::string& what) {
  const hsize_t n[1] = {static_cast<hsize_t>(to)};
  h5::check_status(H5Dset_extent(ds, n), "cannot extend " + what);
  h5::Handle fspace(h5::check(H5Dget_space(ds), "dataspace of " + what), H5Sclose);
  const hsize_t start[1] = {static_cast<hsize_t>(from)}, count[1] = {static_cast<hsize_t>(to - from)};
  h5::check_status(H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr), "selection");
  h5::Handle mspace(h5::check(H5Screate_simple(1, count, nullptr), "memory space"), H5Sclose);
  h5::check_status(H5Dwrite(ds, h5::native_type<T>(), mspace, fspace, H5P_DEFAULT, data.data() + from),
                   "cannot write " + what);
}
}  // namespace

struct History::Writer {
  std::string path;
  h5::Handle file, group, time, step;
  std::vector<h5::Handle> series;
  bool created = false;

  explicit Writer(const std::string& p) : path(p) {
    h5::QuietErrors quiet;
    // No file lock: users watch a running job's history (plot_history.py, h5py), and HDF5's lock
    // would refuse them until the run ends. The file is consistent after every flush.
    h5::Handle fapl(h5::check(H5Pcreate(H5P_FILE_ACCESS), "file access properties"), H5Pclose);
    H5Pset_file_locking(fapl, false, true);
    file = h5::Handle(H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl), H5Fclose);
    if (!file.valid()) throw InputError("cannot create history file '" + p + "' (does its folder exist and is it writable?)");
  }

  void create(const History& h) {
    h5::QuietErrors quiet;
    group = h5::create_group(file, "history", path);
    h5::write_attr_string(group, "format", "rockdem-history", path);
    h5::write_attr<std::int32_t>(group, "version", 1, path);
    time = create_extendible(group, "time", H5T_NATIVE_DOUBLE, path);
    h5::write_attr_string(time, "unit", "s", path);
    h5::write_attr_string(time, "description", "simulated time", path);
    step = create_extendible(group, "step", H5T_NATIVE_INT64, path);
    h5::write_attr_string(step, "unit", "", path);
    h5::write_attr_string(step, "description", "time step number", path);
    for (const auto& s : h.series_) {
      series.push_back(create_extendible(group, s.name, H5T_NATIVE_DOUBLE, path));
      h5::write_attr_string(series.back(), "unit", s.unit, path);
      h5::write_attr_string(series.back(), "description", s.description, path);
    }
    created = true;
  }

  void append_rows(const History& h, std::size_t from, std::size_t to) {
    if (!created) create(h);
    if (to > from) {
      h5::QuietErrors quiet;
      append(time, h.time_, from, to, "/history/time in " + path);
      append(step, h.step_, from, to, "/history/step in " + path);
      for (std::size_t i = 0; i < series.size(); ++i)
        append(series[i], h.data_[i], from, to, "/history/" + h.series_[i].name + " in " + path);
    }
    h5::check_status(H5Fflush(file, H5F_SCOPE_LOCAL), "cannot flush " + path);
  }
};

History::History() = default;
History::~History() {
  try {
    close();
  } catch (...) {  // destructors must not throw; close() explicitly to see the error
  }
}
History::History(History&&) noexcept = default;
History& History::operator=(History&&) noexcept = default;

int History::define(const std::string& name, const std::string& unit, const std::string& description) {
  if (!time_.empty() || (writer_ && writer_->created))
    throw std::logic_error("History::define('" + name + "') after the first sample");
  if (name.empty() || name.find('/') != std::string::npos || name == "time" || name == "step" || name == "." )
    throw InputError("history name '" + name + "' is not valid: use a non-empty name without '/' other than 'time' or 'step'");
  if (id(name) >= 0) throw InputError("history '" + name + "' is defined twice");
  series_.push_back({name, unit, description});
  data_.emplace_back();
  row_.push_back(std::numeric_limits<double>::quiet_NaN());
  return static_cast<int>(series_.size() - 1);
}

int History::id(std::string_view name) const {
  for (std::size_t i = 0; i < series_.size(); ++i)
    if (series_[i].name == name) return static_cast<int>(i);
  return -1;
}

void History::sample(double time, long step, std::span<const double> values) {
  if (values.size() != series_.size())
    throw std::logic_error("History::sample: " + std::to_string(values.size()) + " values for " +
                           std::to_string(series_.size()) + " series");
  time_.push_back(time);
  step_.push_back(step);
  for (std::size_t i = 0; i < values.size(); ++i) data_[i].push_back(values[i]);
  after_append();
}

void History::set(int id, double value) { row_.at(static_cast<std::size_t>(id)) = value; }

void History::commit(double time, long step) {
  time_.push_back(time);
  step_.push_back(step);
  for (std::size_t i = 0; i < row_.size(); ++i) {
    data_[i].push_back(row_[i]);
    row_[i] = std::numeric_limits<double>::quiet_NaN();
  }
  after_append();
}

void History::after_append() {
  if (!writer_) return;
  const std::size_t pending = time_.size() - written_;
  if (pending >= max_pending_) {
    flush();
    return;
  }
  // The clock is read only when something is pending, so an idle History costs nothing.
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_flush_).count() >= max_seconds_) flush();
}

void History::open(const std::string& path) {
  close();
  writer_ = std::make_unique<Writer>(path);
  written_ = 0;
  last_flush_ = std::chrono::steady_clock::now();
}

void History::set_flush_policy(std::size_t max_pending, double max_seconds) {
  max_pending_ = max_pending == 0 ? 1 : max_pending;
  max_seconds_ = max_seconds;
}

void History::flush() {
  if (!writer_) return;
  writer_->append_rows(*this, written_, time_.size());
  written_ = time_.size();
  last_flush_ = std::chrono::steady_clock::now();
}

void History::close() {
  if (!writer_) return;
  flush();
  writer_.reset();
}

void History::write_hdf5(const std::string& path) const {
  Writer w(path);
  w.append_rows(*this, 0, time_.size());
}

}  // namespace rockdem
