#pragma once
// ViewportSurface: the window surface MeshViewport draws on (issue 16 item 5). A QOpenGLWindow, embedded in the
// viewport widget with QWidget::createWindowContainer(), so that a frame is drawn straight into the window's back
// buffer and swapped: no framebuffer object composed into the top-level window as a QOpenGLWidget's is (on Mesa
// llvmpipe under Xvfb that composition cost 12–14 ms per 1024×768 frame, the swap of a window surface ~1.5 ms).
// It owns no scene state: the GL callbacks go to its Client (MeshViewport) and its input events are re-sent to a
// widget (the viewport), so that input handling, QTest events sent to the widget and real pointer events on the
// window all arrive at the same handlers.

#include <QOpenGLWindow>

class QWidget;

namespace sc::app {

class ViewportSurface : public QOpenGLWindow {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(ViewportSurface)

 public:
  /// What the surface calls, with its context current.
  class Client {
   public:
    virtual void initializeSurface() = 0;
    /// Draws one frame into framebuffer object `framebuffer` (the window's: defaultFramebufferObject()).
    virtual void paintSurface(unsigned framebuffer) = 0;
    virtual void resizeSurface(int width, int height) = 0;

   protected:
    virtual ~Client() = default;
  };

  /// @param client  called for the GL work; must outlive the surface's paints (MeshViewport owns the container).
  /// @param input   receives the window's mouse, wheel, key, enter/leave and drag-and-drop events (sent, not
  ///                posted); positions are the window's, which are the widget's when the container fills it.
  ViewportSurface(Client& client, QWidget& input);
  ~ViewportSurface() override;

  /// Paints and swaps now if the window is exposed (a synchronous frame, like QWidget::repaint()); else schedules
  /// one (update()). Returns whether it painted.
  bool paintNow();
  /// Creates the context (and runs Client::initializeSurface()) if the platform window exists and it was not yet
  /// created, then makes it current. Returns whether a context is current on this window now.
  bool makeContextCurrent();

 protected:
  void initializeGL() override;
  void paintGL() override;
  void resizeGL(int width, int height) override;
  /// QOpenGLWindow creates its context at the first resize; before the platform window exists it could not make it
  /// current, so the context waits for a resize or paint with a platform window.
  void resizeEvent(QResizeEvent* event) override;
  bool event(QEvent* event) override;

 private:
  /// Client::initializeSurface() once, when this window's context is current.
  void initializeClient();

  Client& m_client;
  QWidget& m_input;
  const QOpenGLContext* m_initializedContext = nullptr;
};

}  // namespace sc::app
