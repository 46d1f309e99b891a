// The memory bound of a run (--max-memory): steps estimate what they will allocate before they
// allocate it and refuse inputs over the bound with exit 2 and a message giving both numbers,
// instead of being killed by the OOM killer or failing half-way (docs/reliability.md).
#pragma once
#include <cstdint>
#include <string>

namespace al {

// Physical memory, or the cgroup (container) limit when that is lower.
std::uint64_t PhysicalMemoryBytes();

// The bound in bytes. Default: half of PhysicalMemoryBytes() (room for the page cache of the
// inputs and for the allocations no estimate covers).
std::uint64_t MemoryLimitBytes();
void SetMemoryLimitBytes(std::uint64_t bytes);

// "8G", "512M", "1.5GiB", "300000000" (bytes) or "60%" (of physical memory); throws al::Error
// (usage) otherwise or when the result is below 64 MiB.
std::uint64_t ParseMemorySize(const std::string& text);

// "3.2 GiB".
std::string FormatBytes(double bytes);

// Throws al::Error (exit 2) "<what> needs about X, over the memory limit Y (--max-memory)" when
// bytes exceeds the limit.
void CheckMemoryEstimate(const std::string& what, double bytes);

}  // namespace al
