#pragma once
// Helpers shared by the app tests: GL availability, OFF writing, image comparison and position comparison.

#include "app/gui/viewport/renderer_defaults.h"

#include <Eigen/Core>

#include <QColor>
#include <QFile>
#include <QImage>
#include <QOpenGLContext>
#include <QPointF>
#include <QRect>
#include <QString>
#include <QSurfaceFormat>
#include <QTextStream>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <span>
#include <vector>

namespace sc::testing {

/// True when an OpenGL 3.3 core context can be created (an X server with GLX, e.g. Xvfb + Mesa llvmpipe).
/// GL tests skip otherwise, so the suite still runs where there is no display.
inline bool openGlAvailable() { return sc::app::RendererDefaults::openGlProblem().isEmpty(); }

/// Writes (V, F) as an ASCII OFF file; returns false if the file cannot be written.
inline bool writeOff(const QString& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Text)) {
    return false;
  }
  QTextStream out(&file);
  out.setRealNumberPrecision(17);
  out << "OFF\n" << V.rows() << ' ' << F.rows() << " 0\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    out << V(i, 0) << ' ' << V(i, 1) << ' ' << V(i, 2) << '\n';
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    out << "3 " << F(f, 0) << ' ' << F(f, 1) << ' ' << F(f, 2) << '\n';
  }
  return out.status() == QTextStream::Ok;
}

/// Number of pixels whose colour differs between two images by more than `tolerance` steps in a channel (0: any
/// difference); images of different sizes differ everywhere (width·height + 1 of the first).
inline int countDifferentPixels(const QImage& a, const QImage& b, int tolerance = 0) {
  if (a.size() != b.size()) return a.width() * a.height() + 1;
  int count = 0;
  for (int y = 0; y < a.height(); ++y) {
    for (int x = 0; x < a.width(); ++x) {
      const QRgb p = a.pixel(x, y);
      const QRgb q = b.pixel(x, y);
      const bool apart = tolerance == 0
                             ? p != q
                             : std::abs(qRed(p) - qRed(q)) > tolerance || std::abs(qGreen(p) - qGreen(q)) > tolerance ||
                                   std::abs(qBlue(p) - qBlue(q)) > tolerance;
      count += apart ? 1 : 0;
    }
  }
  return count;
}

/// Bounding rectangle of the pixels that differ between two images of the same size (null if none).
inline QRect differingBounds(const QImage& a, const QImage& b) {
  QRect bounds;
  for (int y = 0; y < a.height(); ++y) {
    for (int x = 0; x < a.width(); ++x) {
      if (a.pixel(x, y) != b.pixel(x, y)) {
        bounds |= QRect(x, y, 1, 1);
      }
    }
  }
  return bounds;
}

/// Standard deviation of the grey level over the image: 0 for a blank (uniform) image.
inline double pixelStdDev(const QImage& image) {
  const QImage grey = image.convertToFormat(QImage::Format_Grayscale8);
  double sum = 0.0, sumSq = 0.0;
  const double count = double(grey.width()) * grey.height();
  for (int y = 0; y < grey.height(); ++y) {
    const uchar* row = grey.constScanLine(y);
    for (int x = 0; x < grey.width(); ++x) {
      sum += row[x];
      sumSq += double(row[x]) * row[x];
    }
  }
  const double mean = sum / count;
  return std::sqrt(std::max(0.0, sumSq / count - mean * mean));
}

/// Largest absolute difference of two float buffers (e.g. interleaved positions); infinity when the sizes differ.
inline float maxDifference(std::span<const float> a, std::span<const float> b) {
  if (a.size() != b.size()) return std::numeric_limits<float>::infinity();
  float worst = 0.0f;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  return worst;
}

/// A copy of a float buffer (e.g. a session's positions at one moment, to compare with later ones).
inline std::vector<float> copyOf(std::span<const float> values) { return {values.begin(), values.end()}; }

/// Centroid of the pixels tinted as a handle (orange-red: red high, green and blue low), or (−1, −1) for none.
inline QPointF handleTintCentroid(const QImage& image) {
  double x = 0.0, y = 0.0;
  int count = 0;
  for (int row = 0; row < image.height(); ++row) {
    for (int col = 0; col < image.width(); ++col) {
      const QColor c = image.pixelColor(col, row);
      if (c.red() > 150 && c.red() > 2 * c.green() && c.red() > 3 * c.blue()) {
        x += col;
        y += row;
        ++count;
      }
    }
  }
  return count == 0 ? QPointF(-1.0, -1.0) : QPointF(x / count, y / count);
}

}  // namespace sc::testing
