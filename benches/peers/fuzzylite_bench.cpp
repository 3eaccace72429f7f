// Inference throughput of fuzzylite (C++) on FLL engines, on the same inputs and in the same
// format as strider's `examples/fuzzy_peer.rs`, so the two can be compared line by line.
//
// usage: fuzzylite_bench SECONDS RESOLUTIONS FILE.fll...
//   RESOLUTIONS is a comma-separated list (e.g. 100,200,500): every integral defuzzifier of
//   the engine is set to each in turn.
//
// Inputs: 4096 rows per engine from a 64-bit LCG seeded with 1 (state = state ·
// 6364136223846793005 + 1442695040888963407, value = top 53 bits / 2^53), one value per input
// variable in declaration order, scaled to the variable's range. The rows are cycled for
// SECONDS; the first rows' outputs are printed as `check` lines.

#include <fl/Headers.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Lcg {
    std::uint64_t state;
    double next() {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
    }
};

const std::size_t kRows = 4096;
const std::size_t kChecks = 4;

std::vector<double> inputs_for(const fl::Engine& engine) {
    Lcg rng{1};
    std::vector<double> rows;
    for (std::size_t r = 0; r < kRows; ++r) {
        for (std::size_t i = 0; i < engine.numberOfInputVariables(); ++i) {
            const fl::InputVariable* v = engine.getInputVariable(i);
            const double u = rng.next();
            rows.push_back(v->getMinimum() + u * (v->getMaximum() - v->getMinimum()));
        }
    }
    return rows;
}

void set_row(fl::Engine* engine, const double* row) {
    for (std::size_t i = 0; i < engine->numberOfInputVariables(); ++i) {
        engine->getInputVariable(i)->setValue(row[i]);
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: %s SECONDS RESOLUTIONS FILE.fll...\n", argv[0]);
        return 2;
    }
    const double seconds = std::atof(argv[1]);
    std::vector<int> resolutions;
    {
        std::stringstream list(argv[2]);
        std::string item;
        while (std::getline(list, item, ',')) {
            resolutions.push_back(std::atoi(item.c_str()));
        }
    }
    for (int f = 3; f < argc; ++f) {
        fl::Engine* engine = 0;
        try {
            engine = fl::FllImporter().fromFile(argv[f]);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: %s\n", argv[f], e.what());
            return 1;
        }
        std::string status;
        if (!engine->isReady(&status)) {
            std::fprintf(stderr, "%s: engine not ready: %s\n", argv[f], status.c_str());
            return 1;
        }
        const std::vector<double> rows = inputs_for(*engine);
        const std::size_t n_in = engine->numberOfInputVariables();
        const std::size_t n_out = engine->numberOfOutputVariables();
        for (std::size_t k = 0; k < resolutions.size(); ++k) {
            for (std::size_t o = 0; o < n_out; ++o) {
                fl::IntegralDefuzzifier* d =
                    dynamic_cast<fl::IntegralDefuzzifier*>(engine->getOutputVariable(o)->getDefuzzifier());
                if (d) d->setResolution(resolutions[k]);
            }
            for (std::size_t r = 0; r < kChecks; ++r) {
                set_row(engine, &rows[r * n_in]);
                engine->process();
                std::printf("check %s %d %zu in", engine->getName().c_str(), resolutions[k], r);
                for (std::size_t i = 0; i < n_in; ++i) std::printf(" %.17g", rows[r * n_in + i]);
                std::printf(" out");
                for (std::size_t o = 0; o < n_out; ++o) {
                    std::printf(" %.17g", engine->getOutputVariable(o)->getValue());
                }
                std::printf("\n");
            }
            double sink = 0.0;
            std::uint64_t count = 0;
            const auto start = std::chrono::steady_clock::now();
            double elapsed = 0.0;
            while (elapsed < seconds) {
                for (std::size_t r = 0; r < kRows; ++r) {
                    set_row(engine, &rows[r * n_in]);
                    engine->process();
                    sink += engine->getOutputVariable(0)->getValue();
                }
                count += kRows;
                elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            }
            std::printf("fuzzylite %-10s resolution %4d: %10.0f inferences/s (%llu in %.3f s)%s\n",
                        engine->getName().c_str(), resolutions[k], count / elapsed,
                        static_cast<unsigned long long>(count), elapsed, sink == 12345.678 ? " " : "");
        }
        delete engine;
    }
    return 0;
}
