#pragma once
// The loss experiment (issue 4 item 8; the paper's Figures 3 and 4) with a real SessionHost and real
// SessionClients on loopback, all in this process and on its event loop:
//   - one host (reference Keyframe every frame, so every frame of the drag has an exact reference);
//   - one driver client that holds the edit lock and plays the default drag (defaultLossDrag()) at 30 fps;
//   - per loss ratio, six measuring clients with the same seeded impairment on receive: {full, low level} ×
//     {hold-last, zero-fill, extrapolate}; each records, per frame, what it displayed (DistortionMeter, Record
//     mode; with extrapolate that includes the predicted frames, FramePredictor).
// After each drag the recorded (shown, exact) pairs are measured offline (vertex-set Hausdorff at the client's own
// resolution, % of the full rest bounding-box diagonal), so kd-tree work never delays datagram processing.

#include "app/cli/drag_script.h"
#include "experiments/loss/loss_experiment_report.h"
#include "session/engine/host_model.h"

#include <QString>

#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace sc::app {

struct LossExperimentSettings {
  std::vector<double> losses{0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5};
  bool burst = false;         ///< Gilbert–Elliott instead of Bernoulli loss
  double burstLength = 3.0;   ///< mean burst length in datagrams (burst only)
  double lowFraction = 0.05;  ///< the low level: the ladder level closest to this fraction of the vertices
  std::uint64_t seed = 1;     ///< impairment seed (the same for the six clients of one ratio)
  int threads = 2;            ///< threads for the offline Hausdorff measurements
};

/// The default drag: a handle sphere of 5% of the rest bbox diagonal around the vertex with the largest x (an
/// extremity), moved by 15% of the diagonal along +y over 3 s and back over 3 s at 30 fps; anchors: every vertex
/// farther than 40% of the diagonal from it.
DragScript defaultLossDrag(const Eigen::MatrixXd& rest);

/// Runs the experiment; `progress` (optional) gets one line per step. Returns the rows (per loss ratio: full
/// hold-last, full zero-fill, full extrapolate, then the same at the low level), or an error text.
std::variant<std::vector<LossRow>, QString> runLossExperiment(std::shared_ptr<const session::HostModel> model,
                                                              const LossExperimentSettings& settings,
                                                              const std::function<void(const QString&)>& progress);

}  // namespace sc::app
