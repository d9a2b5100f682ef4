#include "app/common/password_memory.h"

#include <algorithm>

namespace sc::app {

void forgetPassword(std::optional<QString>& password) {
  if (password && password->isDetached()) std::fill(password->begin(), password->end(), QChar(u'\0'));
  password.reset();
}

}  // namespace sc::app
