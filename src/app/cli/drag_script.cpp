#include "app/cli/drag_script.h"

#include "spectral/hausdorff.h"

#include <Eigen/Geometry>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>

namespace sc::app {
namespace {

/// Most frames a script may expand to (about an hour at 30 fps): guards against a typo such as fps = 1e9.
constexpr double kMaxFrames = 100000;
/// Times closer than this (seconds) count as equal when sampling frames.
constexpr double kTimeEpsilon = 1e-9;

/// Thrown inside the parser only (never out of this file): the message names the offending key.
struct ScriptError {
  QString message;
};

[[noreturn]] void fail(const QString& where, const QString& problem) {
  throw ScriptError{where + QStringLiteral(": ") + problem};
}

QString child(const QString& where, const QString& key) {
  return where.isEmpty() ? key : where + QLatin1Char('.') + key;
}

QString element(const QString& where, qsizetype index) {
  return where + QLatin1Char('[') + QString::number(index) + QLatin1Char(']');
}

QJsonObject object(const QJsonValue& value, const QString& where, std::initializer_list<const char*> allowed) {
  if (!value.isObject()) fail(where, QStringLiteral("must be an object"));
  const QJsonObject o = value.toObject();
  QStringList keys;
  for (const char* key : allowed) keys << QLatin1String(key);
  for (const QString& key : o.keys())
    if (!keys.contains(key))
      fail(child(where, key),
           QStringLiteral("unknown key (expected one of: ") + keys.join(QStringLiteral(", ")) + QLatin1Char(')'));
  return o;
}

QJsonValue required(const QJsonObject& o, const QString& where, const char* key) {
  if (!o.contains(QLatin1String(key))) fail(child(where, QLatin1String(key)), QStringLiteral("missing"));
  return o[QLatin1String(key)];
}

double number(const QJsonValue& value, const QString& where) {
  if (!value.isDouble() || !std::isfinite(value.toDouble())) fail(where, QStringLiteral("must be a number"));
  return value.toDouble();
}

double positive(const QJsonValue& value, const QString& where) {
  const double x = number(value, where);
  if (x <= 0.0) fail(where, QStringLiteral("must be positive"));
  return x;
}

int vertexIndex(const QJsonValue& value, const QString& where) {
  const double x = number(value, where);
  if (x < 0 || x != std::floor(x) || x > std::numeric_limits<int>::max())
    fail(where, QStringLiteral("must be a vertex index (a non-negative integer)"));
  return static_cast<int>(x);
}

std::vector<int> vertexList(const QJsonValue& value, const QString& where) {
  if (!value.isArray() || value.toArray().isEmpty())
    fail(where, QStringLiteral("must be a non-empty array of vertex indices"));
  const QJsonArray array = value.toArray();
  std::vector<int> vertices;
  for (qsizetype i = 0; i < array.size(); ++i) vertices.push_back(vertexIndex(array[i], element(where, i)));
  return vertices;
}

Eigen::Vector3d vector3(const QJsonValue& value, const QString& where) {
  if (!value.isArray() || value.toArray().size() != 3) fail(where, QStringLiteral("must be an array of 3 numbers"));
  const QJsonArray array = value.toArray();
  return {number(array[0], element(where, 0)), number(array[1], element(where, 1)),
          number(array[2], element(where, 2))};
}

HandleSelection handle(const QJsonValue& value, const QString& where) {
  const QJsonObject o = object(value, where, {"vertices", "sphere"});
  if (o.contains(QStringLiteral("vertices")) == o.contains(QStringLiteral("sphere")))
    fail(where, QStringLiteral("needs exactly one of \"vertices\" or \"sphere\""));
  HandleSelection h;
  if (o.contains(QStringLiteral("vertices"))) {
    h.vertices = vertexList(o[QStringLiteral("vertices")], child(where, QStringLiteral("vertices")));
    return h;
  }
  const QString at = child(where, QStringLiteral("sphere"));
  const QJsonObject sphere = object(o[QStringLiteral("sphere")], at, {"vertex", "radius_pct"});
  h.sphere = SphereSelection{vertexIndex(required(sphere, at, "vertex"), child(at, QStringLiteral("vertex"))),
                             positive(required(sphere, at, "radius_pct"), child(at, QStringLiteral("radius_pct")))};
  return h;
}

AnchorSelection anchors(const QJsonValue& value) {
  const QString where = QStringLiteral("anchors");
  const QJsonObject o = object(value, where, {"vertices", "farther_than_pct", "from_vertex"});
  AnchorSelection a;
  if (o.contains(QStringLiteral("vertices"))) {
    if (o.contains(QStringLiteral("farther_than_pct")) || o.contains(QStringLiteral("from_vertex")))
      fail(where, QStringLiteral("needs either \"vertices\" or \"farther_than_pct\" with \"from_vertex\", not both"));
    a.vertices = vertexList(o[QStringLiteral("vertices")], child(where, QStringLiteral("vertices")));
    return a;
  }
  const double pct = number(required(o, where, "farther_than_pct"), QStringLiteral("anchors.farther_than_pct"));
  if (pct < 0.0) fail(QStringLiteral("anchors.farther_than_pct"), QStringLiteral("must not be negative"));
  a.fartherThan =
      FartherThanSelection{vertexIndex(required(o, where, "from_vertex"), QStringLiteral("anchors.from_vertex")), pct};
  return a;
}

std::vector<DragKeyframe> keyframes(const QJsonValue& value) {
  const QString where = QStringLiteral("frames");
  if (!value.isArray() || value.toArray().isEmpty()) fail(where, QStringLiteral("must be a non-empty array"));
  const QJsonArray array = value.toArray();
  std::vector<DragKeyframe> frames;
  for (qsizetype i = 0; i < array.size(); ++i) {
    const QString at = element(where, i);
    const QJsonObject o = object(array[i], at, {"t", "translate_pct", "rotate_deg"});
    DragKeyframe k;
    k.t = number(required(o, at, "t"), child(at, QStringLiteral("t")));
    if (!frames.empty() && k.t <= frames.back().t)
      fail(child(at, QStringLiteral("t")), QStringLiteral("must be greater than the previous keyframe's t"));
    if (o.contains(QStringLiteral("translate_pct")))
      k.pose.translatePct = vector3(o[QStringLiteral("translate_pct")], child(at, QStringLiteral("translate_pct")));
    if (o.contains(QStringLiteral("rotate_deg")))
      k.pose.rotateDeg = vector3(o[QStringLiteral("rotate_deg")], child(at, QStringLiteral("rotate_deg")));
    frames.push_back(k);
  }
  return frames;
}

DragScript script(const QJsonValue& root) {
  if (!root.isObject()) fail(QStringLiteral("(root)"), QStringLiteral("must be a JSON object"));
  const QJsonObject o = object(root, QString(), {"handles", "anchors", "frames", "fps", "description"});
  DragScript s;
  const QJsonValue handles = required(o, QString(), "handles");
  if (!handles.isArray() || handles.toArray().isEmpty())
    fail(QStringLiteral("handles"), QStringLiteral("must be a non-empty array of handle groups"));
  const QJsonArray handleArray = handles.toArray();
  for (qsizetype i = 0; i < handleArray.size(); ++i)
    s.handles.push_back(handle(handleArray[i], element(QStringLiteral("handles"), i)));
  if (o.contains(QStringLiteral("anchors"))) s.anchors = anchors(o[QStringLiteral("anchors")]);
  s.frames = keyframes(required(o, QString(), "frames"));
  if (o.contains(QStringLiteral("fps"))) s.fps = positive(o[QStringLiteral("fps")], QStringLiteral("fps"));
  if (o.contains(QStringLiteral("description")) && !o[QStringLiteral("description")].isString())
    fail(QStringLiteral("description"), QStringLiteral("must be a string"));
  if ((s.frames.back().t - s.frames.front().t) * s.fps > kMaxFrames)
    fail(QStringLiteral("fps"), QStringLiteral("too many frames (more than %1)").arg(kMaxFrames));
  return s;
}

/// Vertices whose distance to vertex `from` satisfies `keep`, in index order.
template <class Keep>
std::vector<int> verticesByDistance(const Eigen::MatrixXd& rest, int from, Keep keep) {
  std::vector<int> selected;
  for (Eigen::Index i = 0; i < rest.rows(); ++i)
    if (keep((rest.row(i) - rest.row(from)).norm())) selected.push_back(static_cast<int>(i));
  return selected;
}

void checkRange(const std::vector<int>& vertices, Eigen::Index count, const QString& where) {
  for (int v : vertices)
    if (v >= count)
      fail(where, QStringLiteral("vertex %1 is out of range (the mesh has %2 vertices)").arg(v).arg(count));
}

std::vector<int> sortedUnique(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

std::vector<int> handleVertices(const HandleSelection& h, const Eigen::MatrixXd& rest, double diagonal,
                                const QString& where) {
  if (!h.sphere) {
    checkRange(h.vertices, rest.rows(), child(where, QStringLiteral("vertices")));
    return sortedUnique(h.vertices);
  }
  checkRange({h.sphere->vertex}, rest.rows(), where + QStringLiteral(".sphere.vertex"));
  const double radius = h.sphere->radiusPct / 100.0 * diagonal;
  return verticesByDistance(rest, h.sphere->vertex, [radius](double d) { return d <= radius; });
}

std::vector<int> anchorVertices(const AnchorSelection& a, const Eigen::MatrixXd& rest, double diagonal) {
  if (!a.fartherThan) {
    checkRange(a.vertices, rest.rows(), QStringLiteral("anchors.vertices"));
    return sortedUnique(a.vertices);
  }
  checkRange({a.fartherThan->fromVertex}, rest.rows(), QStringLiteral("anchors.from_vertex"));
  const double limit = a.fartherThan->distancePct / 100.0 * diagonal;
  std::vector<int> selected =
      verticesByDistance(rest, a.fartherThan->fromVertex, [limit](double d) { return d > limit; });
  if (selected.empty()) fail(QStringLiteral("anchors.farther_than_pct"), QStringLiteral("selects no vertex"));
  return selected;
}

spectral::ConstraintSet resolve(const DragScript& script, const Eigen::MatrixXd& rest) {
  const double diagonal = spectral::boundingBoxDiagonal(rest);
  spectral::ConstraintSet set;
  std::vector<int> taken;  // sorted union of the groups so far
  for (std::size_t g = 0; g < script.handles.size(); ++g) {
    const QString where = element(QStringLiteral("handles"), static_cast<qsizetype>(g));
    std::vector<int> group = handleVertices(script.handles[g], rest, diagonal, where);
    std::vector<int> shared;
    std::set_intersection(group.begin(), group.end(), taken.begin(), taken.end(), std::back_inserter(shared));
    if (!shared.empty())
      fail(where, QStringLiteral("shares %1 vertices (e.g. %2) with an earlier handle group")
                      .arg(shared.size())
                      .arg(shared.front()));
    std::vector<int> merged;
    std::merge(group.begin(), group.end(), taken.begin(), taken.end(), std::back_inserter(merged));
    taken = std::move(merged);
    set.handles.push_back({std::move(group)});
  }
  for (int v : anchorVertices(script.anchors, rest, diagonal))
    if (!std::binary_search(taken.begin(), taken.end(), v)) set.anchors.push_back(v);
  return set;
}

}  // namespace

std::variant<DragScript, QString> parseDragScript(const QByteArray& json) {
  QJsonParseError error{};
  const QJsonDocument document = QJsonDocument::fromJson(json, &error);
  if (error.error != QJsonParseError::NoError)
    return QStringLiteral("not valid JSON at offset %1: %2").arg(error.offset).arg(error.errorString());
  try {
    return script(document.isObject() ? QJsonValue(document.object()) : QJsonValue(document.array()));
  } catch (const ScriptError& e) {
    return e.message;
  }
}

std::variant<DragScript, QString> readDragScript(const QString& path) {
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly))
    return QStringLiteral("cannot read drag script '%1': %2").arg(path, file.errorString());
  std::variant<DragScript, QString> parsed = parseDragScript(file.readAll());
  if (auto* message = std::get_if<QString>(&parsed))
    *message = QStringLiteral("drag script '%1': %2").arg(path, *message);
  return parsed;
}

std::variant<spectral::ConstraintSet, QString> resolveConstraints(const DragScript& script,
                                                                  const Eigen::MatrixXd& rest) {
  try {
    return resolve(script, rest);
  } catch (const ScriptError& e) {
    return e.message;
  }
}

std::vector<double> frameTimes(const DragScript& script) {
  const double t0 = script.frames.front().t, tEnd = script.frames.back().t;
  const auto steps = static_cast<long>(std::floor((tEnd - t0) * script.fps + kTimeEpsilon));
  std::vector<double> times;
  for (long k = 0; k <= steps; ++k) times.push_back(t0 + static_cast<double>(k) / script.fps);
  if (tEnd - times.back() > kTimeEpsilon) times.push_back(tEnd);
  return times;
}

DragPose poseAt(const DragScript& script, double t) {
  const std::vector<DragKeyframe>& k = script.frames;
  if (t <= k.front().t) return k.front().pose;
  if (t >= k.back().t) return k.back().pose;
  const auto next = std::upper_bound(k.begin(), k.end(), t, [](double x, const DragKeyframe& f) { return x < f.t; });
  const DragKeyframe& a = *(next - 1);
  const DragKeyframe& b = *next;
  const double s = (t - a.t) / (b.t - a.t);
  return {(1 - s) * a.pose.translatePct + s * b.pose.translatePct, (1 - s) * a.pose.rotateDeg + s * b.pose.rotateDeg};
}

spectral::HandleTransform transformAt(const DragPose& pose, double diagonal) {
  const Eigen::Vector3d radians = pose.rotateDeg * (std::numbers::pi / 180.0);
  spectral::HandleTransform transform;
  transform.translation = pose.translatePct / 100.0 * diagonal;
  transform.rotation = (Eigen::AngleAxisd(radians.z(), Eigen::Vector3d::UnitZ()) *
                        Eigen::AngleAxisd(radians.y(), Eigen::Vector3d::UnitY()) *
                        Eigen::AngleAxisd(radians.x(), Eigen::Vector3d::UnitX()))
                           .toRotationMatrix();
  return transform;
}

}  // namespace sc::app
