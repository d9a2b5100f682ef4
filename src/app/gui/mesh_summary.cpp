#include "app/gui/mesh_summary.h"

#include <QStringList>

namespace sc::app {

namespace {

QString counted(int count, const QString& singular, const QString& plural) {
  return QString::number(count) + QLatin1Char(' ') + (count == 1 ? singular : plural);
}

}  // namespace

QString meshSizeText(int vertexCount, int triangleCount) {
  return counted(vertexCount, QStringLiteral("vertex"), QStringLiteral("vertices")) + QStringLiteral(", ") +
         counted(triangleCount, QStringLiteral("triangle"), QStringLiteral("triangles"));
}

QString cleaningSummary(const model::MeshCleanReport& report) {
  QStringList changes;
  const auto addChange = [&changes](int count, const char* verb, const char* singular, const char* plural) {
    if (count > 0) {
      changes << QLatin1String(verb) + QLatin1Char(' ') +
                     counted(count, QLatin1String(singular), QLatin1String(plural));
    }
  };
  addChange(report.mergedDuplicateVertices, "merged", "duplicate vertex", "duplicate vertices");
  addChange(report.droppedRepeatedIndexFaces, "dropped", "face with a repeated index", "faces with a repeated index");
  addChange(report.droppedZeroAreaFaces, "dropped", "zero-area face", "zero-area faces");
  addChange(report.droppedDuplicateFaces, "dropped", "duplicate face", "duplicate faces");
  addChange(report.droppedUnreferencedVertices, "dropped", "unreferenced vertex", "unreferenced vertices");

  const QString found =
      counted(report.components, QStringLiteral("component"), QStringLiteral("components")) + QStringLiteral(", ") +
      counted(report.boundaryLoops, QStringLiteral("hole"), QStringLiteral("holes")) + QStringLiteral(", ") +
      counted(report.nonManifoldEdges, QStringLiteral("non-manifold edge"), QStringLiteral("non-manifold edges")) +
      QLatin1Char('.');
  if (changes.isEmpty()) {
    return QStringLiteral("Mesh is clean. ") + found;
  }
  return QStringLiteral("Cleaned: ") + changes.join(QStringLiteral(", ")) + QStringLiteral(". ") + found;
}

}  // namespace sc::app
