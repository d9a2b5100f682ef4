#include "model/soup_importer.h"

#include <limits>

namespace sc::model::detail {

SoupImporter::SoupImporter(const std::istream& source, std::uintmax_t sourceBytes)
    : m_source(source), m_sourceBytes(sourceBytes) {}

void SoupImporter::takeSoup(Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  V.resize(static_cast<Eigen::Index>(m_points.size()), 3);
  for (std::size_t v = 0; v < m_points.size(); ++v) {
    for (int k = 0; k < 3; ++k) V(static_cast<Eigen::Index>(v), k) = m_points[v][static_cast<std::size_t>(k)];
  }
  F.resize(static_cast<Eigen::Index>(m_triangles.size()), 3);
  for (std::size_t f = 0; f < m_triangles.size(); ++f) {
    for (int k = 0; k < 3; ++k) F(static_cast<Eigen::Index>(f), k) = m_triangles[f][static_cast<std::size_t>(k)];
  }
  m_points = {};
  m_triangles = {};
}

void SoupImporter::requireReadableSource() const {
  if (m_source.fail()) {
    throw ImportAborted("the stream failed");  // readTriangleSoup() words this
  }
}

OpenMesh::VertexHandle SoupImporter::addPoint(double x, double y, double z) {
  requireReadableSource();
  if (m_points.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw ImportAborted("more vertices than an int index can address");
  }
  m_points.push_back({x, y, z});
  return OpenMesh::VertexHandle(static_cast<int>(m_points.size() - 1));
}

OpenMesh::VertexHandle SoupImporter::add_vertex(const OpenMesh::Vec3f& point) {
  return addPoint(static_cast<double>(point[0]), static_cast<double>(point[1]), static_cast<double>(point[2]));
}

OpenMesh::VertexHandle SoupImporter::add_vertex(const OpenMesh::Vec3d& point) {
  return addPoint(point[0], point[1], point[2]);
}

OpenMesh::VertexHandle SoupImporter::add_vertex() { return addPoint(0.0, 0.0, 0.0); }

void SoupImporter::set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& point) {
  requireReadableSource();
  if (!vh.is_valid() || static_cast<std::size_t>(vh.idx()) >= m_points.size()) {
    throw ImportAborted("the reader set the position of a vertex it never added");
  }
  m_points[static_cast<std::size_t>(vh.idx())] = {static_cast<double>(point[0]), static_cast<double>(point[1]),
                                                  static_cast<double>(point[2])};
}

OpenMesh::FaceHandle SoupImporter::add_face(const VHandles& corners) {
  requireReadableSource();
  const std::string face = "face " + std::to_string(m_polygonCount);
  if (corners.size() < 3) {
    throw ImportAborted(face + " has " + std::to_string(corners.size()) + " corners; a face needs at least 3");
  }
  for (const OpenMesh::VertexHandle vh : corners) {
    if (!vh.is_valid() || static_cast<std::size_t>(vh.idx()) >= m_points.size()) {
      throw ImportAborted(face + " refers to vertex index " + std::to_string(vh.idx()) + " (counting from 0), but " +
                          std::to_string(m_points.size()) + " vertices were read");
    }
  }
  // === fan triangulation around the first corner
  const auto first = static_cast<int>(m_triangles.size());
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
    m_triangles.push_back({corners[0].idx(), corners[k].idx(), corners[k + 1].idx()});
  }
  ++m_polygonCount;
  return OpenMesh::FaceHandle(first);
}

void SoupImporter::reserve(unsigned int nV, unsigned int /*nE*/, unsigned int nF) {
  if (nV > m_sourceBytes || nF > m_sourceBytes) {
    throw ImportAborted("the header declares " + std::to_string(nV) + " vertices and " + std::to_string(nF) +
                        " faces, more than a file of " + std::to_string(m_sourceBytes) + " bytes can hold");
  }
  m_declaredVertices = nV;
  m_declaredFaces = nF;
  m_points.reserve(nV);
  m_triangles.reserve(nF);
}

}  // namespace sc::model::detail
