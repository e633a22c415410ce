// ProcessUsage: what this process has used so far, as Linux reports it (for bench and reports).
#pragma once

namespace imx {

// The process's peak resident memory (its high-water mark), in bytes.
double peak_resident_bytes();

// CPU seconds the process has used on all its threads: the work done, which processes sharing
// cores cannot inflate the way they inflate wall time.
double process_cpu_seconds();

}  // namespace imx
