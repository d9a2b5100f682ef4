#pragma once
// Keeps the shared libraries of the test process mapped until exit, for LeakSanitizer (sanitiser job).

namespace sc::testing {

/// Marks every shared library loaded now as never unloaded (a new dlopen reference with RTLD_NODELETE, never
/// closed). Why: Mesa's GL driver (swrast_dri.so, libGLX_mesa.so, LLVM) keeps blocks in its own globals, and at exit
/// it is unloaded (dlclose: the display's close, libglvnd's teardown) before LeakSanitizer runs; the blocks then look
/// leaked and their stacks show only `<unknown module>`. With the libraries still mapped, LSan scans their globals as
/// it does ours, so a block is reported only if nothing points to it. Cost: one dlopen per loaded library (about 100 in
/// a GL test), each only a lookup of an object already loaded. Fails silently: a library that cannot be reopened is
/// left as it was.
void keepLoadedLibrariesMapped();

}  // namespace sc::testing
