#pragma once
// Running the SciPy peer (bench/scipy_basis_peer.py) from shapecast-bench-basis: finding a Python that has SciPy,
// and running the script on a problem folder (bench/scipy_peer_problem.h) as a child process.

#include <QJsonObject>
#include <QString>
#include <QStringList>

#include <optional>

namespace sc::bench {

/// A Python interpreter that imports SciPy.
struct ScipyPython {
  QString executable;
  QString scipyVersion;
};

/// The first of `candidates` (executables, looked up in PATH) for which `python -c "import scipy"` succeeds within
/// 60 s; std::nullopt when none does (SciPy not installed). Cost: one short process per candidate tried.
std::optional<ScipyPython> findScipyPython(const QStringList& candidates);

/// Runs `python script folder` and returns the JSON object of its last stdout line; std::nullopt, with the reason
/// in `error`, when it fails, runs over `timeoutMs` (then it is killed) or prints no JSON object.
std::optional<QJsonObject> runScipyPeer(const ScipyPython& python, const QString& script, const QString& folder,
                                        int timeoutMs, QString& error);

}  // namespace sc::bench
