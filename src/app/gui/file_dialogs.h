#pragma once
// The window's file questions (open a mesh or session, save a session, export, screenshot) as data, answered by a
// FileChooser: by default a QFileDialog started in the folder last used with a suggested name; tests answer
// without a modal dialog (MainWindow::setFileChooser()).

#include <QString>

#include <functional>

class QWidget;

namespace sc::app {

/// One file question.
struct FileRequest {
  enum class Kind { Open, Save };
  Kind kind = Kind::Open;
  QString title;
  QString folder;         ///< where the dialog starts
  QString suggestedName;  ///< a Save dialog's proposed file name (empty: none)
  QString filter;         ///< QFileDialog name filters ("Meshes (*.off *.obj);;All files (*)")
};

/// The chosen path, or empty when the user cancelled; `selectedFilter` (may be null) gets the filter chosen.
using FileChooser = std::function<QString(const FileRequest& request, QString* selectedFilter)>;

/// A modal QFileDialog for `request` (getOpenFileName / getSaveFileName with folder/suggestedName).
QString chooseInFileDialog(QWidget* parent, const FileRequest& request, QString* selectedFilter);

/// `path` with `suffix` (no dot) appended when it has none.
[[nodiscard]] QString withSuffix(const QString& path, const QString& suffix);

}  // namespace sc::app
