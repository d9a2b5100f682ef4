#pragma once
// Meshes generated in code for the unit tests: exact, small and independent of any file.

#include <Eigen/Core>

namespace sc::testing {

/// A mesh as (V, F): #V by 3 positions, #F by 3 counter-clockwise (outward) indices.
struct GeneratedMesh {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
};

/// Icosahedron subdivided `subdivisions` times, every vertex projected onto the sphere (center, radius).
/// 10·4^s + 2 vertices: s = 3 gives 642, s = 4 gives 2562.
GeneratedMesh icosphere(int subdivisions, double radius = 1.0, const Eigen::Vector3d& center = {0, 0, 0});

/// Torus around the z axis, major radius R, minor radius r, on a u × v grid (closed, genus 1).
GeneratedMesh torus(int u, int v, double R = 1.0, double r = 0.3);

/// Flat open square [0,1]² in the z = 0 plane, nx × ny quads each split into two triangles (has a boundary).
GeneratedMesh grid(int nx, int ny);

/// Open cylinder (a tube without caps) along +x from x = 0 to `length`, radius r, `around` × `along` quads.
/// Has two boundary loops; used as a bar to bend.
GeneratedMesh tube(int around, int along, double length = 4.0, double r = 0.25);

/// Two disjoint icospheres (unit radius, centres 3 apart): two connected components.
GeneratedMesh twoSpheres(int subdivisions);

/// Three components: twoSpheres(4) (every eigenvalue doubled) and a torus(48, 16) beside them.
GeneratedMesh twoSpheresAndATorus();

/// a and b as one mesh of two components: b's vertices follow a's, b's faces renumbered.
GeneratedMesh joined(const GeneratedMesh& a, const GeneratedMesh& b);

}  // namespace sc::testing
