#pragma once
// Resident-set probes of this process, for the renderers' --stats-json.

#include <cstddef>

namespace subdivtrace::tools {

/// Peak resident set size of this process (VmHWM), in bytes; 0 if unknown.
std::size_t peak_rss_bytes();
/// Current resident set size (VmRSS), in bytes; 0 if unknown.
std::size_t current_rss_bytes();
/// Resets the peak (VmHWM) to the current RSS (Linux: /proc/self/clear_refs,
/// value 5), so a later peak_rss_bytes() measures from now. False if it could not.
bool reset_peak_rss();

}  // namespace subdivtrace::tools
