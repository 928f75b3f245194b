#pragma once

// The accuracy-versus-time report: each section measures the error of a technique at each
// setting of its precision knob beside the time it costs, in one run, and returns tables.

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace orbis::bench {

struct Options {
    bool quick = false; ///< fewer samples: a smoke run for the tests, not figures to publish
};

struct Table {
    std::string title;
    std::string description; ///< what was measured and how, in a sentence or two
    std::vector<std::string> columns;
    std::vector<std::vector<std::string>> rows;
    std::string notes; ///< what the figures show
};

using SectionFunction = std::vector<Table> (*)(const Options&);

/// Registers a section at static-initialisation time; sections run in ascending order.
struct SectionRegistration {
    SectionRegistration(const char* name, int order, SectionFunction function);
};

/// Keeps the compiler from discarding a computed value.
template <typename T>
inline void doNotOptimize(const T& value)
{
    asm volatile("" : : "r,m"(value) : "memory");
}

/// Best wall-clock time of `repeats` runs of `run`, divided by `items`, in nanoseconds.
double nanosecondsPerItem(std::size_t items, const std::function<void()>& run, int repeats = 5);

/// This thread's CPU time for `run`, per item, in nanoseconds: time the machine's other work
/// takes from the thread does not count (the figures are for one core, whoever else runs).
double threadCpuNanosecondsPerItem(std::size_t items, const std::function<void()>& run);

/// A length in metres with a readable unit ("3.2 nm", "7.1 mm", "12 km").
std::string formatLength(double meters);
/// A number with the given significant digits.
std::string formatNumber(double value, int significantDigits = 3);

} // namespace orbis::bench
