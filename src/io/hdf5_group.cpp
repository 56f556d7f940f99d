#include "virtual_triaxial/io/hdf5_group.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace vt::io::h5 {

namespace {
// Object creation properties without modification-time tracking, so that the
// same content always gives the same bytes (reproducible sample files).
hid_t untimed_creation_plist(hid_t cls) {
  const hid_t p = H5Pcreate(cls);
  if (p >= 0) H5Pset_obj_track_times(p, false);
  return p;
}


template <class T>
struct Traits;
template <>
struct Traits<double> {
  static hid_t mem() { return H5T_NATIVE_DOUBLE; }
  static hid_t file() { return H5T_IEEE_F64LE; }
  static constexpr H5T_class_t cls = H5T_FLOAT;
  static constexpr const char* name = "floating-point";
};
template <>
struct Traits<std::int64_t> {
  static hid_t mem() { return H5T_NATIVE_INT64; }
  static hid_t file() { return H5T_STD_I64LE; }
  static constexpr H5T_class_t cls = H5T_INTEGER;
  static constexpr const char* name = "integer";
};
template <>
struct Traits<std::int32_t> {
  static hid_t mem() { return H5T_NATIVE_INT32; }
  static hid_t file() { return H5T_STD_I32LE; }
  static constexpr H5T_class_t cls = H5T_INTEGER;
  static constexpr const char* name = "integer";
};
template <>
struct Traits<std::uint64_t> {
  static hid_t mem() { return H5T_NATIVE_UINT64; }
  static hid_t file() { return H5T_STD_U64LE; }
  static constexpr H5T_class_t cls = H5T_INTEGER;
  static constexpr const char* name = "integer";
};
template <>
struct Traits<std::uint8_t> {
  static hid_t mem() { return H5T_NATIVE_UINT8; }
  static hid_t file() { return H5T_STD_U8LE; }
  static constexpr H5T_class_t cls = H5T_INTEGER;
  static constexpr const char* name = "integer";
};

std::string shape_text(const std::vector<hsize_t>& dims) {
  if (dims.empty()) return "scalar";
  std::string s = "(";
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i) s += ", ";
    s += std::to_string(dims[i]);
  }
  return s + ")";
}

Handle vlen_string_type() {
  Handle t = datatype_handle(H5Tcopy(H5T_C_S1));
  if (!t || H5Tset_size(t.get(), H5T_VARIABLE) < 0 || H5Tset_cset(t.get(), H5T_CSET_UTF8) < 0)
    throw std::runtime_error(with_reason("HDF5: cannot make a string type"));
  return t;
}

herr_t collect_link(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

herr_t collect_attr(hid_t, const char* name, const H5A_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}

}  // namespace

// ---- object attribute helpers -------------------------------------------------

void write_string_attr(hid_t obj, const std::string& name, const std::string& value) {
  ErrorSilencer quiet;
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  Handle type = vlen_string_type();
  Handle space = dataspace_handle(H5Screate(H5S_SCALAR));
  Handle attr = attribute_handle(H5Acreate2(obj, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
  const char* p = value.c_str();
  if (!space || !attr || H5Awrite(attr.get(), type.get(), &p) < 0)
    throw std::runtime_error(with_reason("attribute " + name + ": cannot write"));
}

bool read_string_attr(hid_t obj, const std::string& name, std::string& out, const std::string& what) {
  ErrorSilencer quiet;
  if (H5Aexists(obj, name.c_str()) <= 0) return false;
  Handle attr = attribute_handle(H5Aopen(obj, name.c_str(), H5P_DEFAULT));
  Handle ftype = datatype_handle(attr ? H5Aget_type(attr.get()) : H5I_INVALID_HID);
  Handle space = dataspace_handle(attr ? H5Aget_space(attr.get()) : H5I_INVALID_HID);
  if (!attr || !ftype || !space) throw std::runtime_error(with_reason(what + ": cannot open"));
  if (H5Tget_class(ftype.get()) != H5T_STRING) throw std::runtime_error(what + ": not a string");
  if (H5Sget_simple_extent_npoints(space.get()) != 1) throw std::runtime_error(what + ": not a single string");
  if (H5Tis_variable_str(ftype.get()) > 0) {
    Handle mem = datatype_handle(H5Tcopy(H5T_C_S1));
    if (!mem || H5Tset_size(mem.get(), H5T_VARIABLE) < 0 ||
        H5Tset_cset(mem.get(), H5Tget_cset(ftype.get())) < 0)
      throw std::runtime_error(with_reason(what + ": cannot make a string type"));
    char* p = nullptr;
    if (H5Aread(attr.get(), mem.get(), &p) < 0) throw std::runtime_error(with_reason(what + ": cannot read"));
    out = p ? p : "";
    if (p) H5free_memory(p);
  } else {
    const std::size_t size = H5Tget_size(ftype.get());
    std::vector<char> buf(size + 1, '\0');
    if (H5Aread(attr.get(), ftype.get(), buf.data()) < 0)
      throw std::runtime_error(with_reason(what + ": cannot read"));
    out.assign(buf.data(), strnlen(buf.data(), size));
    if (H5Tget_strpad(ftype.get()) == H5T_STR_SPACEPAD)
      while (!out.empty() && out.back() == ' ') out.pop_back();
  }
  return true;
}

// ---- Group -----------------------------------------------------------------------

Group Group::open_file_read(const std::string& file) {
  ErrorSilencer quiet;
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0)
    throw std::runtime_error(file + ": cannot open: " + std::strerror(errno));
  if (H5Fis_hdf5(file.c_str()) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    throw std::runtime_error(file + ": not an HDF5 file");
  }
  Handle f = file_handle(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!f) throw std::runtime_error(with_reason(file + ": cannot open"));
  // The file stays open while the root group is (weak close degree).
  Handle root = group_handle(H5Gopen2(f.get(), "/", H5P_DEFAULT));
  if (!root) throw std::runtime_error(with_reason(file + ": cannot open the root group"));
  return Group(std::move(root), file, "/");
}

std::string Group::child_path(const std::string& name) const {
  if (name.empty()) return path_;
  return path_ == "/" ? "/" + name : path_ + "/" + name;
}

std::string Group::where(const std::string& name) const { return file_ + ": " + child_path(name); }

void Group::fail(const std::string& name, const std::string& reason) const {
  throw std::runtime_error(where(name) + ": " + reason);
}

bool Group::has(const std::string& name) const {
  ErrorSilencer quiet;
  const htri_t r = H5Lexists(id(), name.c_str(), H5P_DEFAULT);
  H5Eclear2(H5E_DEFAULT);
  return r > 0;
}

Group Group::create_group(const std::string& name) const {
  ErrorSilencer quiet;
  const hid_t gcpl = untimed_creation_plist(H5P_GROUP_CREATE);
  Handle g = group_handle(H5Gcreate2(id(), name.c_str(), H5P_DEFAULT, gcpl, H5P_DEFAULT));
  H5Pclose(gcpl);
  if (!g) fail(name, with_reason("cannot create group"));
  return Group(std::move(g), file_, child_path(name));
}

Group Group::open_group(const std::string& name) const {
  ErrorSilencer quiet;
  if (!has(name)) fail(name, "missing");
  Handle g = group_handle(H5Gopen2(id(), name.c_str(), H5P_DEFAULT));
  if (!g) fail(name, with_reason("not a group"));
  return Group(std::move(g), file_, child_path(name));
}

std::vector<std::string> Group::children() const {
  ErrorSilencer quiet;
  std::vector<std::string> names;
  hsize_t idx = 0;
  if (H5Literate(id(), H5_INDEX_NAME, H5_ITER_INC, &idx, &collect_link, &names) < 0)
    fail("", with_reason("cannot list members"));
  return names;
}

template <class T>
void Group::write(const std::string& name, const std::vector<T>& data, std::size_t rows, std::size_t cols,
                  const std::string& units) const {
  ErrorSilencer quiet;
  const std::size_t expected = rows * (cols == 0 ? 1 : cols);
  if (data.size() != expected)
    fail(name, "internal: " + std::to_string(data.size()) + " values for shape " +
                   shape_text(cols == 0 ? std::vector<hsize_t>{rows} : std::vector<hsize_t>{rows, cols}));
  std::vector<hsize_t> dims{static_cast<hsize_t>(rows)};
  if (cols != 0) dims.push_back(static_cast<hsize_t>(cols));
  Handle space = dataspace_handle(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  if (!space) fail(name, with_reason("cannot create dataspace"));
  const hid_t dcpl = untimed_creation_plist(H5P_DATASET_CREATE);
  Handle ds = dataset_handle(H5Dcreate2(id(), name.c_str(), Traits<T>::file(), space.get(), H5P_DEFAULT,
                                        dcpl, H5P_DEFAULT));
  H5Pclose(dcpl);
  if (!ds) fail(name, with_reason("cannot create dataset"));
  if (!data.empty() &&
      H5Dwrite(ds.get(), Traits<T>::mem(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    fail(name, with_reason("cannot write"));
  try {
    write_string_attr(ds.get(), "units", units);
  } catch (const std::exception& e) {
    fail(name, e.what());
  }
}

template <class T>
void Group::write_scalar(const std::string& name, T value, const std::string& units) const {
  ErrorSilencer quiet;
  Handle space = dataspace_handle(H5Screate(H5S_SCALAR));
  if (!space) fail(name, with_reason("cannot create dataspace"));
  const hid_t dcpl = untimed_creation_plist(H5P_DATASET_CREATE);
  Handle ds = dataset_handle(H5Dcreate2(id(), name.c_str(), Traits<T>::file(), space.get(), H5P_DEFAULT,
                                        dcpl, H5P_DEFAULT));
  H5Pclose(dcpl);
  if (!ds) fail(name, with_reason("cannot create dataset"));
  if (H5Dwrite(ds.get(), Traits<T>::mem(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0)
    fail(name, with_reason("cannot write"));
  try {
    write_string_attr(ds.get(), "units", units);
  } catch (const std::exception& e) {
    fail(name, e.what());
  }
}

namespace {

/// Open a dataset, check its type class, return it and its dimensions.
template <class T>
Handle open_dataset(const Group& g, const std::string& name, std::vector<hsize_t>& dims) {
  if (!g.has(name)) g.fail(name, "missing");
  Handle ds = dataset_handle(H5Dopen2(g.id(), name.c_str(), H5P_DEFAULT));
  if (!ds) g.fail(name, with_reason("not a dataset"));
  Handle type = datatype_handle(H5Dget_type(ds.get()));
  Handle space = dataspace_handle(H5Dget_space(ds.get()));
  if (!type || !space) g.fail(name, with_reason("cannot inspect"));
  if (H5Tget_class(type.get()) != Traits<T>::cls)
    g.fail(name, std::string("wrong type, expected ") + Traits<T>::name + " values");
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) g.fail(name, with_reason("cannot read shape"));
  dims.assign(static_cast<std::size_t>(rank), 0);
  if (rank > 0) H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return ds;
}

}  // namespace

std::size_t Group::rows(const std::string& name) const {
  ErrorSilencer quiet;
  if (!has(name)) fail(name, "missing");
  Handle ds = dataset_handle(H5Dopen2(id(), name.c_str(), H5P_DEFAULT));
  if (!ds) fail(name, with_reason("not a dataset"));
  Handle space = dataspace_handle(H5Dget_space(ds.get()));
  const int rank = space ? H5Sget_simple_extent_ndims(space.get()) : -1;
  if (rank < 1 || rank > 2) fail(name, "expected a 1-D or 2-D dataset");
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space.get(), dims, nullptr);
  return static_cast<std::size_t>(dims[0]);
}

template <class T>
std::vector<T> Group::read(const std::string& name, std::size_t rows, std::size_t cols,
                           const std::string& rows_from) const {
  ErrorSilencer quiet;
  std::vector<hsize_t> dims;
  Handle ds = open_dataset<T>(*this, name, dims);
  std::vector<hsize_t> want{static_cast<hsize_t>(rows)};
  if (cols != 0) want.push_back(static_cast<hsize_t>(cols));
  if (dims != want) {
    std::string reason = "inconsistent shape " + shape_text(dims) + ", expected " + shape_text(want);
    if (!rows_from.empty()) reason += " (length of " + rows_from + ")";
    fail(name, reason);
  }
  std::vector<T> out(rows * (cols == 0 ? 1 : cols));
  if (!out.empty() && H5Dread(ds.get(), Traits<T>::mem(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail(name, with_reason("cannot read"));
  return out;
}

template <class T>
T Group::read_scalar(const std::string& name) const {
  ErrorSilencer quiet;
  std::vector<hsize_t> dims;
  Handle ds = open_dataset<T>(*this, name, dims);
  hsize_t n = 1;
  for (hsize_t d : dims) n *= d;
  if (n != 1) fail(name, "expected a single value, found shape " + shape_text(dims));
  T value{};
  if (H5Dread(ds.get(), Traits<T>::mem(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &value) < 0)
    fail(name, with_reason("cannot read"));
  return value;
}

std::string Group::units(const std::string& name) const {
  ErrorSilencer quiet;
  if (!has(name)) fail(name, "missing");
  Handle ds = object_handle(H5Oopen(id(), name.c_str(), H5P_DEFAULT));
  if (!ds) fail(name, with_reason("cannot open"));
  std::string u;
  read_string_attr(ds.get(), "units", u, where(name) + ": units");
  return u;
}

// ---- attributes -------------------------------------------------------------------

bool Group::has_attr(const std::string& name) const {
  ErrorSilencer quiet;
  const htri_t r = H5Aexists(id(), name.c_str());
  H5Eclear2(H5E_DEFAULT);
  return r > 0;
}

std::vector<std::string> Group::attr_names() const {
  ErrorSilencer quiet;
  std::vector<std::string> names;
  hsize_t idx = 0;
  if (H5Aiterate2(id(), H5_INDEX_NAME, H5_ITER_INC, &idx, &collect_attr, &names) < 0)
    fail("", with_reason("cannot list attributes"));
  return names;
}

namespace {

template <class T>
void set_numeric_attr(const Group& g, const std::string& name, T value) {
  ErrorSilencer quiet;
  if (H5Aexists(g.id(), name.c_str()) > 0) H5Adelete(g.id(), name.c_str());
  Handle space = dataspace_handle(H5Screate(H5S_SCALAR));
  Handle attr = attribute_handle(
      H5Acreate2(g.id(), name.c_str(), Traits<T>::file(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!space || !attr || H5Awrite(attr.get(), Traits<T>::mem(), &value) < 0)
    g.fail("", with_reason("attribute " + name + ": cannot write"));
}

template <class T>
T get_numeric_attr(const Group& g, const std::string& name, bool allow_int) {
  ErrorSilencer quiet;
  const std::string what = g.where("") + ": attribute " + name;
  if (H5Aexists(g.id(), name.c_str()) <= 0) throw std::runtime_error(what + ": missing");
  Handle attr = attribute_handle(H5Aopen(g.id(), name.c_str(), H5P_DEFAULT));
  Handle type = datatype_handle(attr ? H5Aget_type(attr.get()) : H5I_INVALID_HID);
  Handle space = dataspace_handle(attr ? H5Aget_space(attr.get()) : H5I_INVALID_HID);
  if (!attr || !type || !space) throw std::runtime_error(with_reason(what + ": cannot open"));
  const H5T_class_t cls = H5Tget_class(type.get());
  if (!(cls == Traits<T>::cls || (allow_int && cls == H5T_INTEGER)))
    throw std::runtime_error(what + ": wrong type, expected " + Traits<T>::name + " value");
  if (H5Sget_simple_extent_npoints(space.get()) != 1) throw std::runtime_error(what + ": not a single value");
  T value{};
  if (H5Aread(attr.get(), Traits<T>::mem(), &value) < 0) throw std::runtime_error(with_reason(what + ": cannot read"));
  return value;
}

H5T_class_t attr_class(const Group& g, const std::string& name) {
  ErrorSilencer quiet;
  Handle attr = attribute_handle(H5Aopen(g.id(), name.c_str(), H5P_DEFAULT));
  Handle type = datatype_handle(attr ? H5Aget_type(attr.get()) : H5I_INVALID_HID);
  if (!type) {
    H5Eclear2(H5E_DEFAULT);
    return H5T_NO_CLASS;
  }
  return H5Tget_class(type.get());
}

}  // namespace

void Group::set_attr(const std::string& name, double value) const { set_numeric_attr(*this, name, value); }
void Group::set_attr(const std::string& name, std::int64_t value) const { set_numeric_attr(*this, name, value); }
void Group::set_attr(const std::string& name, const std::string& value) const {
  try {
    write_string_attr(id(), name, value);
  } catch (const std::exception& e) {
    fail("", e.what());
  }
}

double Group::attr_double(const std::string& name) const { return get_numeric_attr<double>(*this, name, true); }
std::int64_t Group::attr_int(const std::string& name) const {
  return get_numeric_attr<std::int64_t>(*this, name, false);
}

std::string Group::attr_string(const std::string& name) const {
  std::string out;
  const std::string what = where("") + ": attribute " + name;
  if (!read_string_attr(id(), name, out, what)) throw std::runtime_error(what + ": missing");
  return out;
}

bool Group::attr_is_float(const std::string& name) const { return attr_class(*this, name) == H5T_FLOAT; }
bool Group::attr_is_string(const std::string& name) const { return attr_class(*this, name) == H5T_STRING; }

// ---- explicit instantiations -------------------------------------------------------
#define VT_H5_INSTANTIATE(T)                                                                          \
  template void Group::write<T>(const std::string&, const std::vector<T>&, std::size_t, std::size_t, \
                                const std::string&) const;                                           \
  template void Group::write_scalar<T>(const std::string&, T, const std::string&) const;             \
  template std::vector<T> Group::read<T>(const std::string&, std::size_t, std::size_t,               \
                                         const std::string&) const;                                  \
  template T Group::read_scalar<T>(const std::string&) const;

VT_H5_INSTANTIATE(double)
VT_H5_INSTANTIATE(std::int64_t)
VT_H5_INSTANTIATE(std::int32_t)
VT_H5_INSTANTIATE(std::uint64_t)
VT_H5_INSTANTIATE(std::uint8_t)
#undef VT_H5_INSTANTIATE

}  // namespace vt::io::h5
