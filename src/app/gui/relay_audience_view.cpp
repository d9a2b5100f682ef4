#include "app/gui/relay_audience_view.h"

#include <QLocale>

namespace sc::app {
namespace {

const QLocale& english() {
  static const QLocale locale(QLocale::English, QLocale::UnitedStates);
  return locale;
}

QString viewersText(int viewers) {
  return viewers == 1 ? QStringLiteral("1 viewer") : english().toString(viewers) + QStringLiteral(" viewers");
}

QString percent(double fraction) { return english().toString(100.0 * fraction, 'f', 2) + QStringLiteral(" %"); }
QString millis(double ms) { return english().toString(ms, 'f', 1) + QStringLiteral(" ms"); }

/// "; distortion …" over the viewers that measured it (they fetched a level), empty when none did.
QString distortions(const session::RelayAudienceSummary& a) {
  if (a.distortionViewers == 0) return {};
  const auto pct = [](double p) { return english().toString(p, 'f', 3) + QStringLiteral(" %"); };
  return QStringLiteral("; distortion (%1 measuring, mean per viewer) median %2, p90 %3, max %4, largest %5")
      .arg(english().toString(a.distortionViewers), pct(a.distortionMeanPct.median), pct(a.distortionMeanPct.p90),
           pct(a.distortionMeanPct.max), pct(a.distortionMaxPct.max));
}

QString distributions(const session::RelayAudienceSummary& a) {
  return QStringLiteral(
             "loss median %1, p90 %2, max %3; latency p99 (each viewer's last 10 s) median %4, p90 %5, "
             "max %6")
             .arg(percent(a.lossFraction.median), percent(a.lossFraction.p90), percent(a.lossFraction.max),
                  millis(a.latencyP99Ms.median), millis(a.latencyP99Ms.p90), millis(a.latencyP99Ms.max)) +
         distortions(a);
}

}  // namespace

model::PeerRow relayAudienceRow(const session::RelayAudienceSummary& audience) {
  model::PeerRow row;
  row.peerId = kRelayAudienceRowId;
  row.name = viewersText(audience.viewers) + QStringLiteral(" through NATS");
  row.isAudience = true;
  row.hasStats = audience.viewers > 0;
  row.lossPct = 100.0 * audience.lossFraction.median;
  row.latencyP99Ms = audience.latencyP99Ms.median;
  if (row.hasStats) {
    row.figuresToolTip =
        viewersText(audience.viewers) + QStringLiteral(" (reported in the last 10 s): ") + distributions(audience);
  }
  return row;
}

QString relayAudienceText(const session::RelayAudienceSummary& audience) {
  QString text = QStringLiteral("Relay: ") + viewersText(audience.viewers) + QStringLiteral(" through NATS");
  if (audience.viewers == 0) return text + QStringLiteral(" (none reported in the last 10 s)");
  text += QStringLiteral("\n") + distributions(audience);
  if (audience.badSignature > 0)
    text += QStringLiteral("\nforged frames dropped by viewers: ") + english().toString(audience.badSignature);
  if (audience.concealed > 0)
    text += QStringLiteral("\nframes predicted by viewers: ") + english().toString(audience.concealed);
  if (audience.malformed > 0)
    text += QStringLiteral("\nmalformed reports dropped: ") + english().toString(audience.malformed);
  return text;
}

}  // namespace sc::app
