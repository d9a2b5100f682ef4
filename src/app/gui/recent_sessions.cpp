#include "app/gui/recent_sessions.h"

namespace sc::app {

namespace {
const QString kGroup = QStringLiteral("sessions");
}  // namespace

RecentSessions RecentSessions::load(QSettings& settings) {
  RecentSessions recent;
  settings.beginGroup(kGroup);
  const auto list = [&settings](const QString& key) {
    QStringList values = settings.value(key).toStringList();
    values.removeAll(QString());
    while (values.size() > kMaxRecentEntries) values.removeLast();
    return values;
  };
  const auto number = [&settings](const QString& key, int fallback, int low, int high) {
    bool ok = false;
    const int value = settings.value(key, fallback).toInt(&ok);
    return ok && value >= low && value <= high ? value : fallback;
  };
  recent.meshPaths = list(QStringLiteral("meshPaths"));
  recent.hosts = list(QStringLiteral("hosts"));
  recent.names = list(QStringLiteral("names"));
  recent.hostPort = number(QStringLiteral("hostPort"), 47100, 0, 65535);
  recent.joinPort = number(QStringLiteral("joinPort"), 47100, 1, 65535);
  recent.frequencies = number(QStringLiteral("frequencies"), 100, 1, 4096);
  recent.joinResolution = number(QStringLiteral("joinResolution"), 0, 0, 16);
  recent.relayEnabled = settings.value(QStringLiteral("relayEnabled"), false).toBool();
  recent.relayUrl = settings.value(QStringLiteral("relayUrl")).toString();
  recent.relaySessionId = settings.value(QStringLiteral("relaySessionId")).toString();
  recent.relayUser = settings.value(QStringLiteral("relayUser")).toString();
  recent.relayCaFile = settings.value(QStringLiteral("relayCaFile")).toString();
  settings.endGroup();
  return recent;
}

void RecentSessions::save(QSettings& settings) const {
  settings.beginGroup(kGroup);
  settings.setValue(QStringLiteral("meshPaths"), meshPaths);
  settings.setValue(QStringLiteral("hosts"), hosts);
  settings.setValue(QStringLiteral("names"), names);
  settings.setValue(QStringLiteral("hostPort"), hostPort);
  settings.setValue(QStringLiteral("joinPort"), joinPort);
  settings.setValue(QStringLiteral("frequencies"), frequencies);
  settings.setValue(QStringLiteral("joinResolution"), joinResolution);
  settings.setValue(QStringLiteral("relayEnabled"), relayEnabled);
  settings.setValue(QStringLiteral("relayUrl"), relayUrl);
  settings.setValue(QStringLiteral("relaySessionId"), relaySessionId);
  settings.setValue(QStringLiteral("relayUser"), relayUser);
  settings.setValue(QStringLiteral("relayCaFile"), relayCaFile);
  settings.endGroup();
}

void RecentSessions::remember(QStringList& list, const QString& value) {
  const QString trimmed = value.trimmed();
  if (trimmed.isEmpty()) return;
  list.removeAll(trimmed);
  list.prepend(trimmed);
  while (list.size() > kMaxRecentEntries) list.removeLast();
}

void RecentSessions::rememberHost(const HostSettings& settings) {
  remember(meshPaths, settings.meshPath);
  remember(names, settings.name);
  hostPort = settings.port;
  frequencies = settings.m;
  relayEnabled = settings.relay.has_value();
  if (!settings.relay) return;
  relayUrl = settings.relay->url;
  relaySessionId = settings.relay->sessionId;
  relayUser = settings.relay->user;
  relayCaFile = settings.relay->caFile;
}

void RecentSessions::rememberJoin(const JoinSettings& settings) {
  remember(hosts, settings.host);
  remember(names, settings.name);
  joinPort = settings.port;
}

}  // namespace sc::app
