#include "app/gui/peer_colors.h"

#include <array>

namespace sc::app {

QColor peerColor(std::uint32_t peerId) {
  // Eight hues that stay apart from each other and from the mesh's grey, the handle's orange-red and the anchors'
  // blue, and that read on the light gradient background.
  static constexpr std::array<QRgb, kPeerColorCount> kPalette = {
      0x2ca02c,  // green (the host)
      0x9467bd,  // purple
      0x17becf,  // cyan
      0xe377c2,  // pink
      0xbcbd22,  // olive
      0xff7f0e,  // orange
      0x8c564b,  // brown
      0x1f5fb4,  // dark blue
  };
  if (peerId == 0) return QColor(0x80, 0x80, 0x80);
  return QColor::fromRgb(kPalette[(peerId - 1) % kPeerColorCount]);
}

}  // namespace sc::app
