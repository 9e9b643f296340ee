#include "large_pages.hpp"

#if FARFIELD_HAS_MIMALLOC
#include <mimalloc.h>
#endif

namespace farfield::cli {

void use_large_pages() {
#if FARFIELD_HAS_MIMALLOC
  // mimalloc (linked in place of glibc's malloc, so Mesa's buffers and textures come from it
  // too) asks the kernel for 2 MB pages from here on, and keeps what is freed for the next
  // allocation instead of handing it back (a walk's memory is bounded by its cache anyway).
  mi_option_enable(mi_option_large_os_pages);
  mi_option_disable(mi_option_allow_decommit);
#endif
}

}  // namespace farfield::cli
