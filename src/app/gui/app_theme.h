#pragma once
// The application's colours: a dark palette (Fusion style) when the system is dark, else the platform's own.
//
// Qt 6.4 (Debian 12) has no QStyleHints::colorScheme() (Qt 6.5), so the decision is, in order: the environment
// variable SHAPECAST_THEME ("dark" or "light"); with Qt ≥ 6.5 the platform's colour scheme; GTK_THEME naming a
// dark variant ("Adwaita:dark", "Adwaita-dark"); the platform palette's window colour (lightness below 128: dark).

#include <QPalette>
#include <QString>

#include <optional>

namespace sc::app {

enum class ColorScheme { Light, Dark };

/// The decision above from its inputs (pure): `override` is SHAPECAST_THEME's value, `gtkTheme` GTK_THEME's,
/// `platformDark` the platform's colour scheme where Qt reports one, `paletteWindow` the platform palette's window
/// colour.
[[nodiscard]] ColorScheme chooseColorScheme(const QString& override, const QString& gtkTheme,
                                            std::optional<bool> platformDark, const QColor& paletteWindow);

/// The dark palette: dark grey windows and bases, light text, a blue highlight; disabled text dimmed.
[[nodiscard]] QPalette darkPalette();

/// Applies the scheme chosen from this process's environment and platform to the QApplication (which must exist;
/// call it before windows are made).
/// Returns the scheme.
ColorScheme applySystemColorScheme();

}  // namespace sc::app
