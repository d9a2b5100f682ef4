#include "app/gui/background_work.h"

namespace sc::app {

BackgroundWork::~BackgroundWork() {
  cancel();
  join();
}

void BackgroundWork::join() {
  if (m_worker.joinable() && m_worker.get_id() != std::this_thread::get_id()) m_worker.join();
}

}  // namespace sc::app
