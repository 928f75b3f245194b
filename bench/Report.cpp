#include "Report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <thread>

namespace orbis::bench {

namespace {

struct Section {
    std::string name;
    int order;
    SectionFunction function;
};

std::vector<Section>& sections()
{
    static std::vector<Section> all;
    return all;
}

std::string cpuModel()
{
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    while (std::getline(cpuinfo, line)) {
        if (line.rfind("model name", 0) == 0) {
            return line.substr(line.find(':') + 2);
        }
    }
    return "unknown CPU";
}

std::string today()
{
    const std::time_t now = std::time(nullptr);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%d", std::gmtime(&now));
    return text;
}

void writeTable(std::ostream& out, const Table& table)
{
    out << "### " << table.title << "\n\n";
    if (!table.description.empty()) {
        out << table.description << "\n\n";
    }
    out << "|";
    for (const std::string& column : table.columns) {
        out << " " << column << " |";
    }
    out << "\n|";
    for (std::size_t i = 0; i < table.columns.size(); ++i) {
        out << (i == 0 ? " --- |" : " ---: |");
    }
    out << "\n";
    for (const auto& row : table.rows) {
        out << "|";
        for (const std::string& cell : row) {
            out << " " << cell << " |";
        }
        out << "\n";
    }
    out << "\n";
    if (!table.notes.empty()) {
        out << table.notes << "\n\n";
    }
}

int usage()
{
    std::cerr << "usage: orbis_bench [--quick] [--only SECTION] [--out report.md] [--list]\n";
    return 2;
}

} // namespace

SectionRegistration::SectionRegistration(const char* name, int order, SectionFunction function)
{
    sections().push_back({name, order, function});
}

double nanosecondsPerItem(std::size_t items, const std::function<void()>& run, int repeats)
{
    double best = HUGE_VAL;
    for (int i = 0; i < repeats; ++i) {
        const auto start = std::chrono::steady_clock::now();
        run();
        const auto stop = std::chrono::steady_clock::now();
        best = std::min(best, std::chrono::duration<double, std::nano>(stop - start).count());
    }
    return best / static_cast<double>(std::max<std::size_t>(items, 1));
}

double threadCpuNanosecondsPerItem(std::size_t items, const std::function<void()>& run)
{
    timespec start{};
    timespec stop{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &start);
    run();
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &stop);
    const double nanoseconds =
        static_cast<double>(stop.tv_sec - start.tv_sec) * 1e9 + static_cast<double>(stop.tv_nsec - start.tv_nsec);
    return nanoseconds / static_cast<double>(std::max<std::size_t>(items, 1));
}

std::string formatNumber(double value, int significantDigits)
{
    if (value == 0.0 || !std::isfinite(value)) {
        return value == 0.0 ? "0" : (std::isnan(value) ? "NaN" : "inf");
    }
    const int magnitude = static_cast<int>(std::floor(std::log10(std::abs(value))));
    const int decimals = std::max(0, significantDigits - 1 - magnitude);
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

std::string formatLength(double meters)
{
    struct Unit {
        double scale;
        const char* name;
    };
    static constexpr Unit units[] = {{1e3, "km"}, {1.0, "m"}, {1e-3, "mm"}, {1e-6, "µm"}, {1e-9, "nm"}, {1e-12, "pm"}};
    if (meters == 0.0 || !std::isfinite(meters)) {
        return formatNumber(meters) + " m";
    }
    for (const Unit& unit : units) {
        if (std::abs(meters) >= unit.scale) {
            return formatNumber(meters / unit.scale) + " " + unit.name;
        }
    }
    return formatNumber(meters / 1e-12) + " pm";
}

} // namespace orbis::bench

int main(int argc, char** argv)
{
    using namespace orbis::bench;
    Options options;
    std::string only;
    std::string outPath;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) {
            options.quick = true;
        } else if (std::strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
            only = argv[++i];
        } else if (std::strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            outPath = argv[++i];
        } else if (std::strcmp(argv[i], "--list") == 0) {
            for (const Section& section : sections()) {
                std::cout << section.name << "\n";
            }
            return 0;
        } else {
            return usage();
        }
    }

    auto& all = sections();
    std::sort(all.begin(), all.end(), [](const Section& a, const Section& b) { return a.order < b.order; });

    std::ostringstream report;
    report << "# Accuracy versus time\n\n"
           << "Each table sets the error of a technique beside what it costs, measured in one run.\n"
           << "Produced by `build/bin/orbis_bench" << (options.quick ? " --quick" : "")
           << (only.empty() ? "" : " --only " + only) << " --out <this file>` on " << today() << ", "
           << cpuModel() << ", " << std::thread::hardware_concurrency() << " hardware threads, compiler "
           << __VERSION__ << ", Release build.\n\n";

    bool ran = false;
    for (const Section& section : all) {
        if (!only.empty() && section.name != only) {
            continue;
        }
        ran = true;
        std::cerr << "orbis_bench: running " << section.name << "...\n";
        report << "## " << section.name << "\n\n";
        for (const Table& table : section.function(options)) {
            writeTable(report, table);
        }
    }
    if (!ran) {
        std::cerr << "orbis_bench: no section named '" << only << "'\n";
        return 2;
    }

    std::cout << report.str();
    if (!outPath.empty()) {
        std::ofstream out(outPath);
        out << report.str();
        if (!out) {
            std::cerr << "orbis_bench: cannot write " << outPath << "\n";
            return 1;
        }
    }
    return 0;
}
