// The session library is filled in by the session issue; this translation unit keeps the target buildable.
namespace sc::session {
int protocolRevision() { return 0; }
}  // namespace sc::session
