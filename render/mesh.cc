#include "render/mesh.h"

#include <Eigen/Geometry>

namespace dt {
namespace {

void Push(std::vector<float>& xyz, std::vector<uint8_t>& rgba, const Eigen::Vector3d& p,
          Rgba colour) {
  xyz.push_back(static_cast<float>(p.x()));
  xyz.push_back(static_cast<float>(p.y()));
  xyz.push_back(static_cast<float>(p.z()));
  rgba.insert(rgba.end(), colour.begin(), colour.end());
}

}  // namespace

void Mesh::AddVertex(const Eigen::Vector3d& p, Rgba colour) {
  Push(triangle_xyz, triangle_rgba, p, colour);
}

void Mesh::AddTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                       Rgba colour) {
  AddVertex(a, colour);
  AddVertex(b, colour);
  AddVertex(c, colour);
}

void Mesh::AddQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   const Eigen::Vector3d& d, Rgba colour) {
  AddTriangle(a, b, c, colour);
  AddTriangle(a, c, d, colour);
}

void Mesh::AddLine(const Eigen::Vector3d& a, const Eigen::Vector3d& b, Rgba colour) {
  Push(line_xyz, line_rgba, a, colour);
  Push(line_xyz, line_rgba, b, colour);
}

void Mesh::Clear() {
  triangle_xyz.clear();
  triangle_rgba.clear();
  line_xyz.clear();
  line_rgba.clear();
}

Eigen::Vector3d UpwardNormal(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  if (!(len > 0.0)) return Eigen::Vector3d::UnitY();
  n /= len;
  return n.y() < 0.0 ? Eigen::Vector3d(-n) : n;
}

}  // namespace dt
