#include "keep_libraries_mapped.h"

#include <dlfcn.h>
#include <link.h>

#include <cstddef>
#include <string>
#include <vector>

namespace sc::testing {
namespace {

/// dl_iterate_phdr callback: appends the path of each loaded object to the std::vector<std::string> in `data`.
/// The program itself (empty name) and the vDSO (no path) are not files and are left out.
int collectPath(dl_phdr_info* info, std::size_t /*size*/, void* data) {
  if (info->dlpi_name != nullptr && info->dlpi_name[0] == '/') {
    static_cast<std::vector<std::string>*>(data)->emplace_back(info->dlpi_name);
  }
  return 0;
}

}  // namespace

void keepLoadedLibrariesMapped() {
  std::vector<std::string> paths;
  dl_iterate_phdr(collectPath, &paths);  // the loader's lock is held during the walk: reopen after it
  for (const std::string& path : paths) {
    // RTLD_NOLOAD: only libraries already loaded; RTLD_NODELETE: later dlclose calls leave them mapped.
    dlopen(path.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE);
  }
}

}  // namespace sc::testing
