// numpy arrays <-> visimp::Mesh for the Python module. Checks what the C++ API takes on
// trust from its own readers (dtype, shape, index range), so a wrong array is a ValueError
// naming the argument, never a crash or a silent cast.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp::python {

namespace py = pybind11;

/// A mesh from V (n×3, any float dtype) and F (m×3, any integer dtype, indices in [0, n)).
/// `name` prefixes the errors ("A: F[12, 1] = 40 is not a vertex index (V has 40 rows)").
Mesh mesh_from_arrays(const py::handle& vertices, const py::handle& faces, const std::string& name);

/// A mesh given as a (V, F) pair (metro, image_error).
Mesh mesh_from_pair(const py::handle& pair, const std::string& name);

/// One float per face (m, any float dtype, values in [0, 1]): V(t) passed in by the user.
std::vector<float> face_values_from_array(const py::handle& values, std::size_t faces, const std::string& name);

py::array_t<double> vertices_to_array(const Mesh& mesh);
py::array_t<std::int64_t> faces_to_array(const Mesh& mesh);
py::array_t<float> floats_to_array(const std::vector<float>& values);
py::array_t<double> doubles_to_array(const std::vector<double>& values);

}  // namespace visimp::python
