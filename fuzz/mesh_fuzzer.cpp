// Fuzz target "mesh": loadMesh(), the OFF/OBJ/PLY/STL readers (our ASCII OFF reader, off_reader.h; OpenMesh behind
// reader_guards.h and SoupImporter for the rest) and the cleaning that follows. loadMesh() takes a path, so the input
// is written to a scratch file first.
//
// Input: one mode byte, then the file. Mode (low 2 bits) picks the extension: 0 .off, 1 .obj, 2 .ply, 3 .stl.
// Invariants checked: a loaded mesh has finite positions, at least one face, and every corner indexes V.

#include "fuzz_support.h"
#include "model/mesh_loader.h"

#include <array>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static std::array<sc::fuzz::ScratchFile, 4> files{
      sc::fuzz::ScratchFile("input.off"), sc::fuzz::ScratchFile("input.obj"), sc::fuzz::ScratchFile("input.ply"),
      sc::fuzz::ScratchFile("input.stl")};
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  const sc::model::MeshLoadResult result = sc::model::loadMesh(files[input.mode & 3].write(input.rest));
  if (const auto* mesh = std::get_if<sc::model::LoadedMesh>(&result)) {
    sc::fuzz::check(mesh->V.cols() == 3 && mesh->F.cols() == 3, "three columns of positions and corners");
    sc::fuzz::check(mesh->V.allFinite(), "finite positions");
    sc::fuzz::check(mesh->F.rows() > 0, "at least one face");
    sc::fuzz::check(mesh->F.minCoeff() >= 0 && mesh->F.maxCoeff() < mesh->V.rows(), "corners index V");
  }
  return 0;
}
