#include "app/gui/viewport/picture_presenter.h"

namespace sc::app {

PicturePresenter::PicturePresenter(Host& host) : m_host(host) {
  m_sliceTimer.setSingleShot(true);
  m_sliceTimer.setInterval(0);
  QObject::connect(&m_sliceTimer, &QTimer::timeout, &m_sliceTimer, [this] { drawSlice(); });
}

void PicturePresenter::setMinimumTriangles(int minimumTriangles, int sliceLimit) {
  m_minimumTriangles = minimumTriangles;
  m_picture.setSliceLimit(sliceLimit);
}

bool PicturePresenter::active() const {
  return m_minimumTriangles > 0 && m_host.pictureTriangles() >= m_minimumTriangles && m_host.picturesPossible();
}

PicturePresenter::Paint PicturePresenter::show(unsigned framebuffer, bool interactive, StageClock& stages,
                                               FrameTimes& times) {
  const ProgressivePicture::Key key = m_host.currentPictureKey();
  stages.start();
  if (!m_picture.completeFor(key) && !m_picture.drawing(key)) patch(key);
  const double patchMs = stages.lap();
  const bool complete = m_picture.completeFor(key);
  // Without a proxy, once the window has shown this mesh whole (e.g. wireframe), a still paint draws the rest of the
  // picture, as it would the whole mesh, rather than show the slices so far; an interactive one (a resize) draws the
  // whole mesh, reduced, as before. A brush stroke's press completes the picture (depthForPicking()).
  bool rest = false;
  if (!complete) {
    if (!m_picture.drawing(key)) m_picture.start(key, m_host.pictureTriangles());
    if (m_host.proxyMayDraw()) {
      m_sliceTimer.start();
      return Paint::Proxy;
    }
    rest = m_wholePictureShown && !interactive;
    if (!rest) m_sliceTimer.start();
    if (m_wholePictureShown && !rest) return Paint::Whole;
  }
  stages.start();
  PictureScene scene = m_host.pictureScene();
  times.uploadMs = stages.lap();
  if (rest || m_picture.slices() == 0)
    m_picture.drawNext(scene.gl, scene.passes, scene.buffers, scene.gpu, scene.pass, rest);
  m_picture.blit(scene.gl, framebuffer);
  times.meshMs = patchMs + stages.lap();
  times.triangles = m_host.pictureTriangles();
  times.pictureSlices = m_picture.slices();
  return Paint::Picture;
}

void PicturePresenter::windowPainted(bool shown, bool proxy) {
  m_showingPartial = shown && !m_picture.complete();
  m_showingPicture = shown && !m_showingPartial;
  m_wholePictureShown = m_wholePictureShown || m_showingPicture || (!shown && !proxy);
}

bool PicturePresenter::patch(const ProgressivePicture::Key& key) {
  if (!m_picture.followsShape(key)) return false;
  PictureScene scene = m_host.pictureScene();
  return m_picture.patchTints(scene.gl, scene.passes, scene.buffers, scene.gpu, scene.pass, key);
}

void PicturePresenter::continuePicture() {
  if (!active()) {
    m_host.repaintPicture();
    return;
  }
  const ProgressivePicture::Key key = m_host.currentPictureKey();
  if (m_picture.completeFor(key)) {
    if (!m_showingPicture) m_host.repaintPicture();
    return;
  }
  if (m_picture.followsShape(key) && !m_picture.drawing(key)) {  // new tints: the paint patches the picture
    m_host.repaintPicture();
    return;
  }
  if (!m_picture.drawing(key)) m_picture.start(key, m_host.pictureTriangles());
  m_sliceTimer.start();  // the window keeps its interactive frame until the picture is complete
}

void PicturePresenter::drawSlice() {
  if (!m_picture.drawing() || !active() || !m_host.pictureExposed()) return;
  if (m_host.pictureShapeLagging()) {  // a newer frame: stale, and no reconstruction here to find out
    m_picture.reset();
    return;
  }
  if (!m_host.makePictureCurrent()) return;
  const ProgressivePicture::Key key = m_host.currentPictureKey();
  if (!m_picture.drawing(key) && !patch(key)) {  // changed (a gesture, frames): dropped until things are still
    m_picture.reset();
    m_host.releasePictureContext();
    return;
  }
  PictureScene scene = m_host.pictureScene();
  const bool complete = m_picture.drawNext(scene.gl, scene.passes, scene.buffers, scene.gpu, scene.pass);
  m_host.releasePictureContext();
  if (complete || m_showingPartial) m_host.repaintPicture();
  if (!complete) m_sliceTimer.start();
}

std::optional<DepthImage> PicturePresenter::depthForPicking() {
  if (!active()) return std::nullopt;
  // The picture of this shape and view (tints aside) has this depth: a read-back instead of a pass over the whole
  // mesh (0.4-0.6 s on llvmpipe at a million vertices). One that is not complete (a stroke soon after an orbit) is
  // completed here, for a little more than that pass (it shades too), and shown; the paint after the dab then
  // patches it instead of drawing the whole mesh again.
  const ProgressivePicture::Key key = m_host.currentPictureKey();
  if (key.wireframe) return std::nullopt;
  const bool completing = !m_picture.shapeCompleteFor(key);
  if (completing) {
    if (!m_picture.drawing(key) && !patch(key)) m_picture.start(key, m_host.pictureTriangles());
    PictureScene scene = m_host.pictureScene();
    m_picture.drawNext(scene.gl, scene.passes, scene.buffers, scene.gpu, scene.pass, true);
  }
  DepthImage image = m_picture.readDepth(m_host.pictureGl());
  if (completing) m_host.repaintPicture();
  return image;
}

void PicturePresenter::destroy() {
  m_sliceTimer.stop();
  m_picture.destroy();
  m_showingPartial = m_showingPicture = false;
}

}  // namespace sc::app
