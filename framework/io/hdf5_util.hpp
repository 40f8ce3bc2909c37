#pragma once
// Small RAII layer over the HDF5 C API shared by the history and checkpoint writers. Every failing
// call turns into an exception naming the file and the object, instead of HDF5's error-stack dump.
#include <hdf5.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rockdem::h5 {

// Owns one HDF5 identifier and closes it with the matching H5?close.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer close) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, H5I_INVALID_HID);
      close_ = o.close_;
    }
    return *this;
  }
  ~Handle() { reset(); }
  void reset() {
    if (id_ >= 0 && close_) close_(id_);
    id_ = H5I_INVALID_HID;
  }
  hid_t get() const { return id_; }
  operator hid_t() const { return id_; }  // NOLINT: lets handles go straight into H5 calls
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

// Silences HDF5's automatic error printing for its lifetime (restores the previous handler):
// we report failures ourselves with file and object names.
class QuietErrors {
 public:
  QuietErrors() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

template <class T>
hid_t native_type();
template <>
inline hid_t native_type<double>() { return H5T_NATIVE_DOUBLE; }
template <>
inline hid_t native_type<std::int32_t>() { return H5T_NATIVE_INT32; }
template <>
inline hid_t native_type<std::int64_t>() { return H5T_NATIVE_INT64; }
template <>
inline hid_t native_type<std::uint8_t>() { return H5T_NATIVE_UINT8; }

inline hid_t check(hid_t id, const std::string& what) {
  if (id < 0) throw std::runtime_error("HDF5: " + what);
  return id;
}
inline void check_status(herr_t s, const std::string& what) {
  if (s < 0) throw std::runtime_error("HDF5: " + what);
}

inline Handle create_group(hid_t loc, const std::string& name, const std::string& file) {
  return {check(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                "cannot create group '" + name + "' in " + file),
          H5Gclose};
}
inline Handle open_group(hid_t loc, const std::string& name, const std::string& file) {
  return {check(H5Gopen2(loc, name.c_str(), H5P_DEFAULT), "no group '" + name + "' in " + file), H5Gclose};
}

// Scalar or string attributes on any object. The forms taking an HDF5 type and a pointer serve
// callers that know the element type only at run time (the checkpoint's field tables).
inline void write_attr(hid_t obj, const std::string& name, hid_t type, const void* value,
                       const std::string& file) {
  Handle space(check(H5Screate(H5S_SCALAR), "scalar space"), H5Sclose);
  Handle a(check(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
                 "cannot create attribute '" + name + "' in " + file),
           H5Aclose);
  check_status(H5Awrite(a, type, value), "cannot write attribute '" + name + "' in " + file);
}
template <class T>
void write_attr(hid_t obj, const std::string& name, T value, const std::string& file) {
  write_attr(obj, name, native_type<T>(), &value, file);
}

// Variable-length UTF-8 string: h5py reads it back as str rather than bytes.
inline Handle vlen_string_type() {
  Handle t(check(H5Tcopy(H5T_C_S1), "string type"), H5Tclose);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return t;
}

inline void write_attr_string(hid_t obj, const std::string& name, const std::string& value,
                              const std::string& file) {
  Handle t = vlen_string_type();
  Handle space(check(H5Screate(H5S_SCALAR), "scalar space"), H5Sclose);
  Handle a(check(H5Acreate2(obj, name.c_str(), t, space, H5P_DEFAULT, H5P_DEFAULT),
                 "cannot create attribute '" + name + "' in " + file),
           H5Aclose);
  const char* p = value.c_str();
  check_status(H5Awrite(a, t, &p), "cannot write attribute '" + name + "' in " + file);
}

inline void read_attr(hid_t obj, const std::string& name, hid_t type, void* value, const std::string& file) {
  Handle a(check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "no attribute '" + name + "' in " + file), H5Aclose);
  check_status(H5Aread(a, type, value), "cannot read attribute '" + name + "' in " + file);
}
template <class T>
T read_attr(hid_t obj, const std::string& name, const std::string& file) {
  T v{};
  read_attr(obj, name, native_type<T>(), &v, file);
  return v;
}

inline std::string read_attr_string(hid_t obj, const std::string& name, const std::string& file) {
  Handle a(check(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "no attribute '" + name + "' in " + file), H5Aclose);
  Handle t = vlen_string_type();
  char* p = nullptr;
  check_status(H5Aread(a, t, &p), "cannot read attribute '" + name + "' in " + file);
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

// A one- or two-dimensional dataset written in one go (rows x cols, row-major); one-dimensional
// when cols is 1. The first form takes the element type at run time, like write_attr.
inline void write_dataset(hid_t loc, const std::string& name, hid_t type, const void* data, hsize_t rows,
                          hsize_t cols, const std::string& file) {
  const hsize_t dims[2] = {rows, cols};
  Handle space(check(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), "dataspace for " + name), H5Sclose);
  Handle ds(check(H5Dcreate2(loc, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  "cannot create dataset '" + name + "' in " + file),
            H5Dclose);
  if (rows * cols > 0)
    check_status(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data),
                 "cannot write dataset '" + name + "' in " + file);
}
template <class T>
void write_dataset(hid_t loc, const std::string& name, const std::vector<T>& data, hsize_t rows,
                   hsize_t cols, const std::string& file) {
  if (data.size() != rows * cols) throw std::logic_error("h5::write_dataset: size mismatch for " + name);
  write_dataset(loc, name, native_type<T>(), data.data(), rows, cols, file);
}

// Shape of a dataset as {rows, cols} (cols = 1 for one-dimensional datasets).
inline std::pair<hsize_t, hsize_t> dataset_shape(hid_t ds) {
  Handle space(H5Dget_space(ds), H5Sclose);
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 1 || rank > 2) return {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  return {dims[0], rank == 2 ? dims[1] : 1};
}

}  // namespace rockdem::h5
