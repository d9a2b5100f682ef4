#include "app/gui/viewport/viewport_surface.h"

#include <QCoreApplication>
#include <QEvent>
#include <QOpenGLContext>
#include <QResizeEvent>
#include <QWidget>

namespace sc::app {

ViewportSurface::ViewportSurface(Client& client, QWidget& input)
    : QOpenGLWindow(QOpenGLWindow::NoPartialUpdate), m_client(client), m_input(input) {
  // Keyboard focus stays with the widgets: a press re-sent to the viewport gives it focus (its focus policy), keys
  // reach it through its top-level window and the main window's shortcuts work as with any widget.
  setFlag(Qt::WindowDoesNotAcceptFocus);
}

ViewportSurface::~ViewportSurface() = default;

bool ViewportSurface::paintNow() {
  update();  // marks the whole window dirty (a QPaintDeviceWindow paints only a dirty region)
  if (!isExposed()) {
    return false;
  }
  QEvent request(QEvent::UpdateRequest);
  QCoreApplication::sendEvent(this, &request);
  return true;
}

bool ViewportSurface::makeContextCurrent() {
  if (!isValid() && handle() != nullptr) {
    QResizeEvent resize(size(), size());
    QOpenGLWindow::resizeEvent(&resize);  // creates the context, makes it current, initializeGL()
  }
  if (!isValid()) {
    return false;
  }
  makeCurrent();
  initializeClient();
  return QOpenGLContext::currentContext() == context();
}

void ViewportSurface::initializeClient() {
  // A new context (the first, or one after the platform surface was destroyed) has none of the client's objects.
  if (context() == nullptr || QOpenGLContext::currentContext() != context() || m_initializedContext == context()) {
    return;
  }
  m_initializedContext = context();
  m_client.initializeSurface();
}

void ViewportSurface::initializeGL() { initializeClient(); }

void ViewportSurface::paintGL() {
  initializeClient();
  m_client.paintSurface(defaultFramebufferObject());
}

void ViewportSurface::resizeGL(int width, int height) { m_client.resizeSurface(width, height); }

void ViewportSurface::resizeEvent(QResizeEvent* event) {
  if (handle() == nullptr) {
    m_client.resizeSurface(width(), height());
    return;
  }
  QOpenGLWindow::resizeEvent(event);
}

bool ViewportSurface::event(QEvent* event) {
  switch (event->type()) {
    case QEvent::MouseButtonPress:
    case QEvent::MouseButtonRelease:
    case QEvent::MouseButtonDblClick:
    case QEvent::MouseMove:
    case QEvent::Wheel:
    case QEvent::KeyPress:
    case QEvent::KeyRelease:
    case QEvent::Enter:
    case QEvent::Leave:
    case QEvent::DragEnter:  // files dropped on the view: the widgets decide (the main window opens them)
    case QEvent::DragMove:
    case QEvent::DragLeave:
    case QEvent::Drop:
      QCoreApplication::sendEvent(&m_input, event);
      return true;
    default:
      return QOpenGLWindow::event(event);
  }
}

}  // namespace sc::app
