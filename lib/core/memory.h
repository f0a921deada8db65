// core/memory.h: the process's resident memory, for the memory figures of run reports.
#pragma once

#include <cstdint>

namespace inlight {

/// Peak resident set size of this process so far (VmHWM of /proc/self/status), bytes; 0 when
/// the platform does not report it.
uint64_t peak_rss_bytes();
/// Current resident set size (VmRSS), bytes; 0 when not reported.
uint64_t current_rss_bytes();
/// The machine's physical memory (MemTotal of /proc/meminfo), bytes; 0 when not reported.
uint64_t physical_memory_bytes();

}  // namespace inlight
