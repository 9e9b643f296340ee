// Walks (bench, view) take memory in 2 MB pages. A streamed walk fills its cache of GPU
// buffers and textures as it goes, and with 4 KB pages every new one is a page fault per 4 KB
// on the frame's thread: on the 2-core test VM first touch costs 3.6 ms a MB. On the 100M
// city's walks (--cache-mb 1024) 2 MB pages took the faults from 300K to 80-110K and the load
// from 1.5 s to 0.4-0.9 s. Bakes keep the allocator's defaults: their peak memory is what
// bounds them.
#pragma once

namespace farfield::cli {

void use_large_pages();

}  // namespace farfield::cli
