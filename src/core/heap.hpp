#pragma once
// The process heap's policy for a pipeline whose stages allocate and free arrays of hundreds of
// megabytes: peak memory is a target (docs/benchmarks.md), so freed memory must go back to the system.
// glibc-specific; elsewhere these do nothing.

namespace poreshell {

// glibc serves a large block from its heap once a block of that size has been freed (its mmap
// threshold grows), and the heap keeps freed pages: the arrays a stage frees would then count in every
// later peak. A fixed threshold keeps large arrays in mappings of their own, returned when freed.
void keep_large_blocks_mapped();

// Hands freed heap pages back to the system. glibc keeps what many small blocks freed (a band's scan,
// a solver's levels) in its arenas, where it counts in every later peak.
void release_free_memory();

}  // namespace poreshell
