// Keeps memory that the program frees for its next allocations instead of
// handing it back to the kernel.
//
// Why: glibc's malloc serves blocks of 128 KB and more (a threshold that grows
// with what is freed, up to 32 MB) from fresh mmap'd pages and returns freed
// memory at the top of its heaps to the kernel; every reuse then pays a page
// fault per 4 KB page. The fits allocate and free matrices of 0.1–30 MB
// thousands of times (a 297-basis Gram matrix is 0.7 MB, a fold system three of
// them), and on a virtual machine a fault is expensive: `perf` puts a tenth of
// `brdfshot eval`'s time in faults and the kernel's zeroing of fresh pages
// (docs/benchmarks.md, "Set a"). With the heap kept, a freed block is reused as
// it is. The cost is that the process holds the memory of its peak until it
// exits, which a command-line stage does within seconds or minutes anyway.
#pragma once

namespace brdfshot {

// Sets glibc's malloc to serve blocks below 32 MB (its largest allowed
// threshold) from its heaps and never to trim them. Returns whether the
// allocator took the settings (false on other C libraries, where nothing
// changes). `brdfshot` calls it once, before running a command.
bool KeepFreedHeapMemory();

}  // namespace brdfshot
