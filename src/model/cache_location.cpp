#include "model/cache_location.h"

#include <QStandardPaths>

namespace sc::model {

std::filesystem::path basisCacheDirectory() {
  const QString root = QStandardPaths::writableLocation(QStandardPaths::GenericCacheLocation);
  return std::filesystem::path(root.toStdString()) / "shapecast" / "bases";
}

}  // namespace sc::model
