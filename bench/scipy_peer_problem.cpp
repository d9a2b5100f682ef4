#include "scipy_peer_problem.h"

#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>

#include <fstream>
#include <limits>
#include <string>

namespace sc::bench {
namespace {

std::ofstream openExact(const QString& path) {
  std::ofstream out(path.toStdString());
  out.precision(std::numeric_limits<double>::max_digits10);
  return out;
}

bool writeStiffness(const QString& path, const spectral::SparseMatrix& S) {
  Eigen::Index lower = 0;
  for (Eigen::Index col = 0; col < S.outerSize(); ++col)
    for (spectral::SparseMatrix::InnerIterator it(S, col); it; ++it) lower += it.row() >= col ? 1 : 0;
  std::ofstream out = openExact(path);
  out << "%%MatrixMarket matrix coordinate real symmetric\n"
      << "% cotangent stiffness S of shapecast-bench-basis (lower triangle)\n"
      << S.rows() << ' ' << S.cols() << ' ' << lower << '\n';
  for (Eigen::Index col = 0; col < S.outerSize(); ++col)
    for (spectral::SparseMatrix::InnerIterator it(S, col); it; ++it)
      if (it.row() >= col) out << it.row() + 1 << ' ' << col + 1 << ' ' << it.value() << '\n';
  return static_cast<bool>(out.flush());
}

bool writeMass(const QString& path, const Eigen::VectorXd& mass) {
  std::ofstream out = openExact(path);
  for (const double value : mass) out << value << '\n';
  return static_cast<bool>(out.flush());
}

}  // namespace

bool writeScipyPeerProblem(const QString& folder, const spectral::LaplaceOperators& ops, int m, double sigma,
                           const QJsonArray& referenceEigenvalues, QString& error) {
  const QString stiffness = folder + QStringLiteral("/stiffness.mtx");
  const QString mass = folder + QStringLiteral("/mass.txt");
  if (!writeStiffness(stiffness, ops.stiffness)) {
    error = QStringLiteral("cannot write ") + stiffness;
    return false;
  }
  if (!writeMass(mass, ops.mass)) {
    error = QStringLiteral("cannot write ") + mass;
    return false;
  }
  QFile problem(folder + QStringLiteral("/problem.json"));
  const QJsonObject json{{QStringLiteral("m"), m},
                         {QStringLiteral("sigma"), sigma},
                         {QStringLiteral("vertices"), static_cast<qint64>(ops.mass.size())},
                         {QStringLiteral("reference_eigenvalues"), referenceEigenvalues}};
  if (!problem.open(QIODevice::WriteOnly) || problem.write(QJsonDocument(json).toJson()) < 0) {
    error = QStringLiteral("cannot write ") + problem.fileName();
    return false;
  }
  return true;
}

}  // namespace sc::bench
