#pragma once
// Private to shapecast_model: an OpenMesh importer that keeps what a reader delivers as a triangle soup.
// It includes OpenMesh, so no public header may include it.
//
// Why not OpenMesh's own TriMesh: its halfedge add_face() rejects non-manifold faces ("complex edge") and so
// silently drops part of real scans such as the Stanford dragons. This importer accepts every face, checks its
// indices itself, fan-triangulates polygons and leaves repairs to cleanMesh().

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <istream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sc::model::detail {

/// Thrown from inside a reader callback to stop OpenMesh at the first bad item; what() says what was wrong.
/// readTriangleSoup() catches it: it never leaves the model library.
class ImportAborted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Polygon-soup importer for OpenMesh's readers (OFF, OBJ, PLY, STL).
///
/// Every callback first checks the stream the reader consumes: once that stream has failed, the reader is
/// working on values it could not read (a truncated or malformed file), so the callback throws ImportAborted.
/// Faces are validated (at least 3 corners, every index names an already read vertex) and fan-triangulated:
/// (v0 v1 v2), (v0 v2 v3), … Colours, normals, texture coordinates and halfedge data are ignored.
/// Cost: O(1) amortised per vertex and per triangle.
class SoupImporter final : public OpenMesh::IO::BaseImporter {
 public:
  /// @param[in] source      the stream the reader consumes (OBJ, read by file name, passes an idle stream);
  ///                        must outlive the importer.
  /// @param[in] sourceBytes its size: no vertex or face takes less than one byte, so a header that declares
  ///                        more elements than that is rejected before anything is allocated.
  SoupImporter(const std::istream& source, std::uintmax_t sourceBytes);

  /// Moves the soup out: V #vertices by 3, F #triangles by 3 (indices valid in V).
  void takeSoup(Eigen::MatrixXd& V, Eigen::MatrixXi& F);

  std::size_t vertexCount() const { return m_points.size(); }
  std::size_t polygonCount() const { return m_polygonCount; }  ///< faces as in the file, before triangulation
  std::optional<std::size_t> declaredVertices() const { return m_declaredVertices; }  ///< header count, if any
  std::optional<std::size_t> declaredFaces() const { return m_declaredFaces; }        ///< header count, if any

  // === the callbacks the readers use
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& point) override;
  OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& point) override;
  OpenMesh::VertexHandle add_vertex() override;
  void set_point(OpenMesh::VertexHandle vh, const OpenMesh::Vec3f& point) override;
  OpenMesh::FaceHandle add_face(const VHandles& corners) override;
  void reserve(unsigned int nV, unsigned int nE, unsigned int nF) override;
  std::size_t n_vertices() const override { return m_points.size(); }
  std::size_t n_faces() const override { return m_triangles.size(); }
  std::size_t n_edges() const override { return 0; }

  // === callbacks for data a soup does not keep: accepted and ignored
  OpenMesh::HalfedgeHandle add_edge(OpenMesh::VertexHandle, OpenMesh::VertexHandle) override {
    return OpenMesh::HalfedgeHandle();
  }
  OpenMesh::FaceHandle add_face(OpenMesh::HalfedgeHandle) override { return OpenMesh::FaceHandle(); }
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(OpenMesh::FaceHandle, int) override {}
  void set_halfedge(OpenMesh::VertexHandle, OpenMesh::HalfedgeHandle) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(OpenMesh::FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(OpenMesh::FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(OpenMesh::VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(OpenMesh::HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(OpenMesh::VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_status(OpenMesh::HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_status(OpenMesh::FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(OpenMesh::HalfedgeHandle, OpenMesh::HalfedgeHandle) override {}
  void set_face(OpenMesh::HalfedgeHandle, OpenMesh::FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void add_texture_information(int, std::string) override {}

 private:
  /// Throws ImportAborted when the source stream has failed.
  void requireReadableSource() const;
  OpenMesh::VertexHandle addPoint(double x, double y, double z);

  const std::istream& m_source;
  std::uintmax_t m_sourceBytes = 0;
  std::vector<std::array<double, 3>> m_points;
  std::vector<std::array<int, 3>> m_triangles;
  std::size_t m_polygonCount = 0;
  std::optional<std::size_t> m_declaredVertices;
  std::optional<std::size_t> m_declaredFaces;
};

}  // namespace sc::model::detail
