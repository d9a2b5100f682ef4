#include "app/gui/file_dialogs.h"

#include <QDir>
#include <QFileDialog>
#include <QFileInfo>

namespace sc::app {

QString chooseInFileDialog(QWidget* parent, const FileRequest& request, QString* selectedFilter) {
  if (request.kind == FileRequest::Kind::Open) {
    return QFileDialog::getOpenFileName(parent, request.title, request.folder, request.filter, selectedFilter);
  }
  const QString start =
      request.suggestedName.isEmpty() ? request.folder : QDir(request.folder).filePath(request.suggestedName);
  return QFileDialog::getSaveFileName(parent, request.title, start, request.filter, selectedFilter);
}

QString withSuffix(const QString& path, const QString& suffix) {
  if (path.isEmpty() || !QFileInfo(path).suffix().isEmpty()) return path;
  return path + QLatin1Char('.') + suffix;
}

}  // namespace sc::app
