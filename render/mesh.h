// Mesh: coloured triangles and line segments ready for OpenGL vertex arrays.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/image.h"

namespace dt {

// Vertices in world coordinates (x east, y up, z north) as floats, one colour per vertex.
struct Mesh {
  std::vector<float> triangle_xyz;
  std::vector<uint8_t> triangle_rgba;
  std::vector<float> line_xyz;
  std::vector<uint8_t> line_rgba;

  void AddVertex(const Eigen::Vector3d& p, Rgba colour);
  void AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   Rgba colour);
  // A planar quad a-b-c-d (in order around its edge) as two triangles.
  void AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
               const Eigen::Vector3d& d, Rgba colour);
  void AddLine(const Eigen::Vector3d& a, const Eigen::Vector3d& b, Rgba colour);

  size_t triangle_vertex_count() const { return triangle_xyz.size() / 3; }
  size_t line_vertex_count() const { return line_xyz.size() / 3; }
  void Clear();
};

// Unit normal of triangle a-b-c, oriented so its y component is not negative.
Eigen::Vector3d UpwardNormal(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

}  // namespace dt
