// Attributes of File: scalars, arrays and strings on groups and datasets.
#include "io/h5_file.hpp"

#include <hdf5.h>

#include <algorithm>

#include "core/error.hpp"
#include "io/hdf5_internals.hpp"

namespace granudrag::h5 {

using namespace detail;

namespace {

std::string attr_where(const std::string& name, const std::string& path, const std::string& file) {
  return "attribute " + in_quotes(name) + " on " + in_file(path, file);
}

void write_attr(hid_t file, const std::string& file_name, const std::string& raw_path,
                const std::string& name, hid_t file_type, hid_t mem_type, hid_t space, const void* data) {
  const std::string path = canonical(raw_path);
  if (name.empty()) throw Error("empty attribute name for " + in_file(path, file_name));
  const Handle object = open_object(file, file_name, path, true);
  if (H5Aexists(object.get(), name.c_str()) > 0 && H5Adelete(object.get(), name.c_str()) < 0)
    throw Error("cannot replace " + attr_where(name, path, file_name) + hdf5_reason());
  Handle attr(H5Acreate2(object.get(), name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.ok() || (data != nullptr && H5Awrite(attr.get(), mem_type, data) < 0))  // nullptr: no elements
    throw Error("cannot write " + attr_where(name, path, file_name) + hdf5_reason());
}

// A fixed-length string type wide enough for `width` bytes plus the terminating NUL.
Handle fixed_string_type(std::size_t width, bool utf8) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), width + 1);
  H5Tset_strpad(type.get(), H5T_STR_NULLTERM);
  H5Tset_cset(type.get(), utf8 ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
  return type;
}

bool any_non_ascii(const std::vector<std::string>& values) {
  for (const auto& v : values)
    for (unsigned char c : v)
      if (c >= 0x80) return true;
  return false;
}

void write_string_attr(hid_t file, const std::string& file_name, const std::string& path,
                       const std::string& name, const std::vector<std::string>& values, bool scalar) {
  std::size_t width = 0;
  for (const auto& v : values) width = std::max(width, v.size());
  const Handle type = fixed_string_type(width, any_non_ascii(values));
  std::vector<char> buffer(values.size() * (width + 1), '\0');
  for (std::size_t k = 0; k < values.size(); ++k)
    std::copy(values[k].begin(), values[k].end(), buffer.begin() + k * (width + 1));
  const hsize_t n = values.size();
  const Handle space(scalar ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr(file, file_name, path, name, type.get(), type.get(), space.get(), buffer.data());
}

// The type h5py uses for numpy bools: an 8-bit signed enum {FALSE = 0, TRUE = 1}.
Handle flag_type() {
  Handle type(H5Tenum_create(H5T_NATIVE_INT8), H5Tclose);
  const signed char no = 0, yes = 1;
  H5Tenum_insert(type.get(), "FALSE", &no);
  H5Tenum_insert(type.get(), "TRUE", &yes);
  return type;
}

bool is_flag_type(hid_t type) {
  if (H5Tget_class(type) != H5T_ENUM || H5Tget_size(type) != 1 || H5Tget_nmembers(type) != 2) return false;
  for (signed char value : {0, 1}) {
    char name[8] = {};
    if (H5Tenum_nameof(type, &value, name, sizeof name) < 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
    if (std::string(name) != (value ? "TRUE" : "FALSE")) return false;
  }
  return true;
}

struct Attribute {
  Handle attr, type;
  std::size_t count = 0;
  bool scalar = true;
  std::string where;
};

Attribute open_attr(hid_t file, const std::string& file_name, const std::string& raw_path,
                    const std::string& name) {
  const std::string path = canonical(raw_path);
  Attribute a;
  a.where = attr_where(name, path, file_name);
  const Handle object = open_object(file, file_name, path, false);
  if (H5Aexists(object.get(), name.c_str()) <= 0) {
    H5Eclear2(H5E_DEFAULT);
    throw Error("no " + a.where);
  }
  a.attr = Handle(H5Aopen(object.get(), name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.attr.ok()) throw Error("cannot open " + a.where + hdf5_reason());
  a.type = Handle(H5Aget_type(a.attr.get()), H5Tclose);
  const Handle space(H5Aget_space(a.attr.get()), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) throw Error("cannot read the shape of " + a.where + hdf5_reason());
  a.count = static_cast<std::size_t>(n);
  a.scalar = H5Sget_simple_extent_type(space.get()) == H5S_SCALAR;
  return a;
}

template <class T>
std::vector<T> read_numeric_attr(const Attribute& a, Want want) {
  if (!accepts(want, a.type.get()))
    throw Error(a.where + " holds " + describe(a.type.get()) + ", not " + wanted(want));
  std::vector<T> out(a.count);
  if (a.count > 0 && H5Aread(a.attr.get(), memory_type(want), out.data()) < 0)
    throw Error("cannot read " + a.where + hdf5_reason());
  return out;
}

std::vector<std::string> read_string_attr(const Attribute& a) {
  if (H5Tget_class(a.type.get()) != H5T_STRING)
    throw Error(a.where + " holds " + describe(a.type.get()) + ", not strings");
  std::vector<std::string> out;
  out.reserve(a.count);
  if (H5Tis_variable_str(a.type.get()) > 0) {  // as h5py writes str attributes
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem.get(), H5T_VARIABLE);
    H5Tset_cset(mem.get(), H5Tget_cset(a.type.get()));
    std::vector<char*> ptrs(a.count, nullptr);
    if (a.count > 0 && H5Aread(a.attr.get(), mem.get(), ptrs.data()) < 0)
      throw Error("cannot read " + a.where + hdf5_reason());
    for (char* p : ptrs) {
      out.emplace_back(p != nullptr ? p : "");
      if (p != nullptr) H5free_memory(p);
    }
    return out;
  }
  const std::size_t width = H5Tget_size(a.type.get());
  std::vector<char> buffer(a.count * width);
  if (a.count > 0 && H5Aread(a.attr.get(), a.type.get(), buffer.data()) < 0)
    throw Error("cannot read " + a.where + hdf5_reason());
  const bool space_padded = H5Tget_strpad(a.type.get()) == H5T_STR_SPACEPAD;
  for (std::size_t k = 0; k < a.count; ++k) {
    const char* begin = buffer.data() + k * width;
    std::string s(begin, std::find(begin, begin + width, '\0'));
    if (space_padded) s.erase(s.find_last_not_of(' ') + 1);
    out.push_back(std::move(s));
  }
  return out;
}

template <class T>
T only_value(const std::vector<T>& values, const std::string& where, const char* plural_getter) {
  if (values.size() != 1)
    throw Error(where + " holds " + std::to_string(values.size()) + " values, not one" +
                (plural_getter[0] ? std::string("; read it with ") + plural_getter : std::string()));
  return values.front();
}

}  // namespace

void File::set_attr(const std::string& path, const std::string& name, double value) {
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr(id(true), path_, path, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, space.get(), &value);
}

void File::set_attr(const std::string& path, const std::string& name, std::int64_t value) {
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr(id(true), path_, path, name, H5T_STD_I64LE, H5T_NATIVE_INT64, space.get(), &value);
}

void File::set_attr(const std::string& path, const std::string& name, const std::string& value) {
  write_string_attr(id(true), path_, path, name, {value}, true);
}

void File::set_attr(const std::string& path, const std::string& name,
                    const std::vector<std::int64_t>& values) {
  const hsize_t n = values.size();
  const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr(id(true), path_, path, name, H5T_STD_I64LE, H5T_NATIVE_INT64, space.get(), values.data());
}

void File::set_attr(const std::string& path, const std::string& name,
                    const std::vector<std::string>& values) {
  write_string_attr(id(true), path_, path, name, values, false);
}

void File::attr_overflow(const std::string& path, const std::string& name) const {
  throw Error("value of " + attr_where(name, canonical(path), path_) +
              " does not fit in a 64-bit signed integer");
}

bool File::has_attr(const std::string& path, const std::string& name) const {
  const hid_t file = id(false);
  const std::string p = canonical(path);
  if (!object_exists(file, p)) return false;
  const Handle object(H5Oopen(file, p.c_str(), H5P_DEFAULT), H5Oclose);
  const htri_t found = object.ok() ? H5Aexists(object.get(), name.c_str()) : -1;
  H5Eclear2(H5E_DEFAULT);
  return found > 0;
}

double File::get_attr_double(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return only_value(read_numeric_attr<double>(a, Want::Float), a.where, "");
}

std::int64_t File::get_attr_int64(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return only_value(read_numeric_attr<std::int64_t>(a, Want::Int64), a.where, "get_attr_int64s");
}

std::string File::get_attr_string(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return only_value(read_string_attr(a), a.where, "get_attr_strings");
}

std::vector<std::int64_t> File::get_attr_int64s(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return read_numeric_attr<std::int64_t>(a, Want::Int64);
}

std::vector<std::string> File::get_attr_strings(const std::string& path, const std::string& name) const {
  return read_string_attr(open_attr(id(false), path_, path, name));
}

void File::set_attr(const std::string& path, const std::string& name, const std::vector<double>& values) {
  const hsize_t n = values.size();
  const Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr(id(true), path_, path, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, space.get(), values.data());
}

void File::set_flag_attr(const std::string& path, const std::string& name, bool value) {
  const Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle type = flag_type();
  const signed char stored = value ? 1 : 0;
  write_attr(id(true), path_, path, name, type.get(), type.get(), space.get(), &stored);
}

std::vector<double> File::get_attr_doubles(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  return read_numeric_attr<double>(a, Want::Float);
}

bool File::get_attr_flag(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  if (!is_flag_type(a.type.get()))
    throw Error(a.where + " holds " + describe(a.type.get()) + ", not a flag (enum FALSE/TRUE)");
  if (a.count != 1) throw Error(a.where + " holds " + std::to_string(a.count) + " values, not one");
  signed char stored = 0;
  if (H5Aread(a.attr.get(), a.type.get(), &stored) < 0) throw Error("cannot read " + a.where + hdf5_reason());
  return stored != 0;
}

std::vector<std::string> File::attr_names(const std::string& path) const {
  const hid_t file = id(false);
  const Handle object = open_object(file, path_, canonical(path), false);
  std::vector<std::string> names;
  auto collect = [](hid_t, const char* name, const H5A_info_t*, void* out) -> herr_t {
    static_cast<std::vector<std::string>*>(out)->emplace_back(name);
    return 0;
  };
  if (H5Aiterate2(object.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect, &names) < 0)
    throw Error("cannot list the attributes of " + in_file(canonical(path), path_) + hdf5_reason());
  return names;
}

File::AttrShape File::attr_shape(const std::string& path, const std::string& name) const {
  const Attribute a = open_attr(id(false), path_, path, name);
  AttrShape shape;
  shape.scalar = a.scalar;
  shape.count = a.count;
  const hid_t type = a.type.get();
  if (is_flag_type(type))
    shape.type = AttrType::Flag;
  else if (accepts(Want::Float, type))
    shape.type = AttrType::Float;
  else if (accepts(Want::Int64, type))
    shape.type = AttrType::Integer;
  else if (H5Tget_class(type) == H5T_STRING)
    shape.type = AttrType::String;
  return shape;
}

}  // namespace granudrag::h5
