// Tests for src/app/gui/mesh_summary.cpp.

#include "app/gui/mesh_summary.h"

#include <gtest/gtest.h>

using sc::app::cleaningSummary;
using sc::app::meshSizeText;

TEST(MeshSummary, SizeText) {
  EXPECT_EQ(meshSizeText(642, 1280), QStringLiteral("642 vertices, 1280 triangles"));
  EXPECT_EQ(meshSizeText(1, 1), QStringLiteral("1 vertex, 1 triangle"));
  EXPECT_EQ(meshSizeText(0, 0), QStringLiteral("0 vertices, 0 triangles"));
}

TEST(MeshSummary, CleanMesh) {
  sc::model::MeshCleanReport report;
  report.components = 1;
  EXPECT_EQ(cleaningSummary(report), QStringLiteral("Mesh is clean. 1 component, 0 holes, 0 non-manifold edges."));
}

TEST(MeshSummary, ListsOnlyWhatChanged) {
  sc::model::MeshCleanReport report;
  report.mergedDuplicateVertices = 3;
  report.droppedZeroAreaFaces = 1;
  report.components = 2;
  report.boundaryLoops = 1;
  report.nonManifoldEdges = 4;
  EXPECT_EQ(cleaningSummary(report), QStringLiteral("Cleaned: merged 3 duplicate vertices, dropped 1 zero-area face. "
                                                    "2 components, 1 hole, 4 non-manifold edges."));
}
