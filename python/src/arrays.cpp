#include "arrays.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace visimp::python {

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// The argument as an ndarray, without converting lists of the wrong kind silently: a list is
// turned into an array and then held to the same dtype rule as an array.
py::array as_array(const py::handle& h, const std::string& what) {
  if (h.is_none()) throw py::value_error(what + " is None");
  try {
    return py::array::ensure(h);
  } catch (const py::error_already_set&) {
    throw py::value_error(what + " is not an array");
  }
}

py::array checked(const py::handle& h, const std::string& what, char kind_a, char kind_b, const char* kind_text,
                  int columns) {
  py::array a = as_array(h, what);
  if (!a) throw py::value_error(what + " is not an array");
  const char kind = a.dtype().kind();
  if (kind != kind_a && kind != kind_b)
    throw py::value_error(what + " must have " + kind_text + " dtype, got " + std::string(py::str(a.dtype())));
  const bool shape_ok = columns > 0 ? (a.ndim() == 2 && a.shape(1) == columns) : a.ndim() == 1;
  if (!shape_ok)
    throw py::value_error(what + " must have shape " + (columns > 0 ? "(n, " + std::to_string(columns) + ")" : "(n,)") +
                          ", got " + shape_text(a));
  return a;
}

}  // namespace

Mesh mesh_from_arrays(const py::handle& vertices, const py::handle& faces, const std::string& name) {
  const std::string prefix = name.empty() ? "" : name + ": ";
  const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
      checked(vertices, prefix + "V", 'f', 'f', "a floating-point", 3));
  const py::array f_in = checked(faces, prefix + "F", 'i', 'u', "an integer", 3);
  const auto f = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(f_in);
  if (!v || !f) throw py::value_error(prefix + "V or F cannot be converted");
  Mesh mesh;
  const std::size_t n = static_cast<std::size_t>(v.shape(0)), m = static_cast<std::size_t>(f.shape(0));
  if (n > std::size_t{0xFFFFFFFFu}) throw py::value_error(prefix + "V has more rows than 32-bit indices can address");
  mesh.positions.resize(n);
  const double* vp = v.data();
  for (std::size_t i = 0; i < n; ++i) {
    const double x = vp[3 * i], y = vp[3 * i + 1], z = vp[3 * i + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw py::value_error(prefix + "V[" + std::to_string(i) + "] is not finite");
    mesh.positions[i] = {x, y, z};
  }
  mesh.faces.resize(m);
  const std::int64_t* fp = f.data();
  for (std::size_t i = 0; i < m; ++i) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t idx = fp[3 * i + static_cast<std::size_t>(k)];
      if (idx < 0 || static_cast<std::uint64_t>(idx) >= n)
        throw py::value_error(prefix + "F[" + std::to_string(i) + ", " + std::to_string(k) + "] = " +
                              std::to_string(idx) + " is not a vertex index (V has " + std::to_string(n) + " rows)");
      mesh.faces[i][static_cast<std::size_t>(k)] = static_cast<VertexIndex>(idx);
    }
  }
  return mesh;
}

Mesh mesh_from_pair(const py::handle& pair, const std::string& name) {
  if (!py::isinstance<py::tuple>(pair) && !py::isinstance<py::list>(pair))
    throw py::value_error(name + " must be a (V, F) pair");
  const py::sequence s = py::reinterpret_borrow<py::sequence>(pair);
  if (s.size() != 2) throw py::value_error(name + " must be a (V, F) pair, got " + std::to_string(s.size()) + " items");
  return mesh_from_arrays(s[0], s[1], name);
}

std::vector<float> face_values_from_array(const py::handle& values, std::size_t faces, const std::string& name) {
  const auto a =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(checked(values, name, 'f', 'f', "a floating-point", 0));
  if (static_cast<std::size_t>(a.shape(0)) != faces)
    throw py::value_error(name + " must have one value per face (" + std::to_string(faces) + "), got " +
                          std::to_string(a.shape(0)));
  std::vector<float> out(faces);
  for (std::size_t i = 0; i < faces; ++i) {
    const double x = a.data()[i];
    if (!(x >= 0 && x <= 1)) throw py::value_error(name + "[" + std::to_string(i) + "] = " + std::to_string(x) + " is not in [0, 1]");
    out[i] = static_cast<float>(x);
  }
  return out;
}

py::array_t<double> vertices_to_array(const Mesh& mesh) {
  py::array_t<double> a({static_cast<py::ssize_t>(mesh.num_vertices()), py::ssize_t{3}});
  double* p = a.mutable_data();
  for (const Vec3& v : mesh.positions) {
    *p++ = v.x;
    *p++ = v.y;
    *p++ = v.z;
  }
  return a;
}

py::array_t<std::int64_t> faces_to_array(const Mesh& mesh) {
  py::array_t<std::int64_t> a({static_cast<py::ssize_t>(mesh.num_faces()), py::ssize_t{3}});
  std::int64_t* p = a.mutable_data();
  for (const Face& f : mesh.faces)
    for (VertexIndex i : f) *p++ = i;
  return a;
}

py::array_t<float> floats_to_array(const std::vector<float>& values) {
  py::array_t<float> a(static_cast<py::ssize_t>(values.size()));
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(float));
  return a;
}

py::array_t<double> doubles_to_array(const std::vector<double>& values) {
  py::array_t<double> a(static_cast<py::ssize_t>(values.size()));
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(double));
  return a;
}

}  // namespace visimp::python
