#include "app/gui/app_theme.h"

#include <QApplication>
#include <QColor>
#include <QStyleFactory>
#include <QStyleHints>
#include <QtGlobal>

namespace sc::app {

ColorScheme chooseColorScheme(const QString& override, const QString& gtkTheme, std::optional<bool> platformDark,
                              const QColor& paletteWindow) {
  const QString wanted = override.trimmed().toLower();
  if (wanted == QStringLiteral("dark")) return ColorScheme::Dark;
  if (wanted == QStringLiteral("light")) return ColorScheme::Light;
  if (platformDark) return *platformDark ? ColorScheme::Dark : ColorScheme::Light;
  const QString gtk = gtkTheme.toLower();
  if (gtk.endsWith(QStringLiteral(":dark")) || gtk.endsWith(QStringLiteral("-dark"))) return ColorScheme::Dark;
  return paletteWindow.lightness() < 128 ? ColorScheme::Dark : ColorScheme::Light;
}

QPalette darkPalette() {
  const QColor window(45, 45, 48);
  const QColor base(30, 30, 32);
  const QColor text(225, 225, 225);
  const QColor disabled(128, 128, 128);
  QPalette p;
  p.setColor(QPalette::Window, window);
  p.setColor(QPalette::WindowText, text);
  p.setColor(QPalette::Base, base);
  p.setColor(QPalette::AlternateBase, window);
  p.setColor(QPalette::ToolTipBase, base);
  p.setColor(QPalette::ToolTipText, text);
  p.setColor(QPalette::PlaceholderText, disabled);
  p.setColor(QPalette::Text, text);
  p.setColor(QPalette::Button, window);
  p.setColor(QPalette::ButtonText, text);
  p.setColor(QPalette::BrightText, QColor(255, 90, 90));
  p.setColor(QPalette::Light, QColor(70, 70, 74));
  p.setColor(QPalette::Midlight, QColor(58, 58, 62));
  p.setColor(QPalette::Mid, QColor(38, 38, 40));
  p.setColor(QPalette::Dark, QColor(25, 25, 27));
  p.setColor(QPalette::Shadow, QColor(10, 10, 10));
  p.setColor(QPalette::Highlight, QColor(42, 130, 218));
  p.setColor(QPalette::HighlightedText, Qt::white);
  p.setColor(QPalette::Link, QColor(90, 160, 240));
  for (const QPalette::ColorRole role : {QPalette::WindowText, QPalette::Text, QPalette::ButtonText}) {
    p.setColor(QPalette::Disabled, role, disabled);
  }
  p.setColor(QPalette::Disabled, QPalette::Highlight, QColor(70, 70, 74));
  return p;
}

ColorScheme applySystemColorScheme() {
  std::optional<bool> platformDark;
#if QT_VERSION >= QT_VERSION_CHECK(6, 5, 0)
  if (const Qt::ColorScheme scheme = QGuiApplication::styleHints()->colorScheme(); scheme != Qt::ColorScheme::Unknown)
    platformDark = scheme == Qt::ColorScheme::Dark;
#endif
  const ColorScheme scheme =
      chooseColorScheme(qEnvironmentVariable("SHAPECAST_THEME"), qEnvironmentVariable("GTK_THEME"), platformDark,
                        QApplication::palette().color(QPalette::Window));
  if (scheme == ColorScheme::Dark) {
    QApplication::setStyle(QStyleFactory::create(QStringLiteral("Fusion")));
    QApplication::setPalette(darkPalette());
  }
  return scheme;
}

}  // namespace sc::app
