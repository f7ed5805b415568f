#include "render/rss.h"

#include <fstream>
#include <string>

namespace subdivtrace::tools {

namespace {

/// A "Field:   1234 kB" line of /proc/self/status, in bytes.
std::size_t proc_status_bytes(const char* field) {
    std::ifstream status("/proc/self/status");
    std::string line;
    const std::string prefix = std::string(field) + ":";
    while (std::getline(status, line)) {
        if (line.rfind(prefix, 0) == 0) return std::stoull(line.substr(prefix.size())) * 1024;
    }
    return 0;
}

}  // namespace

std::size_t peak_rss_bytes() { return proc_status_bytes("VmHWM"); }
std::size_t current_rss_bytes() { return proc_status_bytes("VmRSS"); }

bool reset_peak_rss() {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    return static_cast<bool>(clear);
}

}  // namespace subdivtrace::tools
