#pragma once
// The store shapecast-cli used before it named its organisation: its known hosts (the "knownHosts" group of
// ~/.config/Unknown Organization/shapecast.conf) and its host's TLS identity (~/.local/share/shapecast/tls), apart
// from the desktop app's (~/.config/ShapeCast/shapecast.conf, ~/.local/share/ShapeCast/shapecast/tls). Both
// executables now name the organisation "ShapeCast" and share one store; this moves the old one into it, once.

#include <QString>

namespace sc::app {

/// Where a store keeps its known hosts (a QSettings INI file) and its host's TLS identity (a folder holding
/// host-key.pem and host-cert.pem).
struct StoreLocations {
  QString settingsFile;
  QString identityDirectory;
};

/// What migrateLegacyStore() did.
struct LegacyStoreMigration {
  bool ran = false;                 ///< false: the current store records an earlier migration, nothing was read
  int hostsCopied = 0;              ///< known hosts the current store did not have
  int hostsKept = 0;                ///< known hosts both had, with different fingerprints: the current store's kept
  bool identityCopied = false;      ///< the old host identity became the current one (the current store had none)
  bool identityReplaced = false;    ///< both had an identity: the current one is used from now on, the old one left
  bool identityFailed = false;      ///< the copy failed (nothing of it left behind): the migration is not recorded
  bool settingsFailed = false;      ///< the current settings file could not be written
  QString legacyIdentityDirectory;  ///< where the old identity is (for the notice)
  /// One readable paragraph for the user when something changed for them (hosts copied or kept, the identity
  /// replaced); empty otherwise.
  QString notice() const;
};

/// Copies the legacy store into the current one, once: every known host the current store lacks (one it has with
/// another fingerprint keeps the current fingerprint), and the host identity when the current store has none
/// (both files or neither, 0600 in a 0700 folder). Then records in the current settings that it ran, so that a host
/// forgotten later does not come back; not when the identity could not be copied (the next run tries again). The legacy
/// files are only read, never changed or removed. A legacy store that does not exist migrates nothing. Cost: one read
/// of each settings file, two small file copies at most.
LegacyStoreMigration migrateLegacyStore(const StoreLocations& legacy, const StoreLocations& current);

/// The legacy store's locations: GenericConfigLocation/"Unknown Organization"/shapecast.conf and
/// GenericDataLocation/shapecast/tls (needs a QCoreApplication).
StoreLocations legacyCommandLineStore();

/// Names this process as both executables do: organisation "ShapeCast", application "shapecast", `version`. Needs
/// a QCoreApplication.
void nameApplication(const QString& version);

/// After nameApplication(): migrateLegacyStore() from legacyCommandLineStore() into QSettings' default file and
/// `identityDirectory` (the session library's defaultTlsIdentityDirectory()); prints its notice, if any, on stderr.
void migrateLegacyStoreIntoThisOne(const QString& identityDirectory);

}  // namespace sc::app
