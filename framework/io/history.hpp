#pragma once
// Histories: named scalar series (with units) sampled at common times, kept in memory and written
// to HDF5 as /history/time, /history/step and /history/<name> (attributes `unit`, `description`).
//
// Two ways to sample, both allocation-free beyond amortised vector growth:
//   h.sample(t, step, values);             // one value per series, in definition order
//   h.set(id, v); ...; h.commit(t, step);  // per-series; series not set in a row are NaN
// With open(path) the file is written incrementally (chunked, extendible datasets, flushed at
// least every `max_pending` samples or `max_seconds` of wall time), so that a long run that dies
// still leaves its history on disk up to the last flush.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rockdem {

class History {
 public:
  struct Series {
    std::string name, unit, description;
  };

  History();
  ~History();  // flushes and closes an open file; errors there are swallowed (use close() to see them)
  History(History&&) noexcept;
  History& operator=(History&&) noexcept;
  History(const History&) = delete;
  History& operator=(const History&) = delete;

  // Declares a series and returns its id (= position in sample()'s values). Only before the first
  // sample. Names must be unique, non-empty, without '/', and not "time" or "step" (InputError).
  int define(const std::string& name, const std::string& unit, const std::string& description = "");

  int id(std::string_view name) const;  // -1 if there is no such series
  std::size_t series_count() const { return series_.size(); }
  std::size_t sample_count() const { return time_.size(); }
  const Series& info(int id) const { return series_.at(static_cast<std::size_t>(id)); }

  // One row: values.size() must equal series_count().
  void sample(double time, long step, std::span<const double> values);
  // Per-series recording of the current row, then commit() appends it (unset values are NaN).
  void set(int id, double value);
  void commit(double time, long step);

  std::span<const double> times() const { return time_; }
  std::span<const std::int64_t> steps() const { return step_; }
  std::span<const double> values(int id) const { return data_.at(static_cast<std::size_t>(id)); }

  // Incremental output: creates (truncates) `path`; everything already sampled goes to disk at the
  // next flush. One open file per History.
  void open(const std::string& path);
  void set_flush_policy(std::size_t max_pending, double max_seconds);
  void flush();  // appends the samples not yet on disk and flushes the file to the OS
  void close();  // flush and close; a no-op if no file is open

  // Writes the whole history to a new file in one go (independent of open()).
  void write_hdf5(const std::string& path) const;

 private:
  struct Writer;
  void after_append();

  std::vector<Series> series_;
  std::vector<double> time_;
  std::vector<std::int64_t> step_;
  std::vector<std::vector<double>> data_;  // one column per series
  std::vector<double> row_;                // the row being set()
  std::unique_ptr<Writer> writer_;
  std::size_t written_ = 0;  // samples already on disk
  std::size_t max_pending_ = 1000;
  double max_seconds_ = 10.0;
  std::chrono::steady_clock::time_point last_flush_{};
};

}  // namespace rockdem
