#pragma once
// Whether the test runs in an AddressSanitizer build (scripts/test.sh's sanitiser job, build-asan/), for the few
// checks that ASan's own memory use or the sanitiser's exit-time leak check make different there.

namespace sc::testing {

/// True in an ASan build: GCC defines __SANITIZE_ADDRESS__, Clang answers __has_feature(address_sanitizer).
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

}  // namespace sc::testing
