// Every seed of the document fuzzer and every reproducer of a finding
// (tests/fuzz/seeds/finding-*), the bundled examples and the command-line
// tests' documents, run through exactly what the fuzzer does with an input
// (tests/fuzz/FuzzDocument.cpp): no finding, within seconds. Under ASan and
// UBSan (tools/test.sh --sanitize) the sanitizers watch it too.

#include "FuzzDocument.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace kerf {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputs()
{
    std::vector<fs::path> files;
    for (const char* dir : {KERF_FUZZ_SEEDS_DIR, KERF_EXAMPLES_DIR, KERF_CLI_DATA_DIR})
        for (const auto& e : fs::directory_iterator(dir))
            if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

class FuzzSeeds : public ::testing::TestWithParam<fs::path> {};

TEST_P(FuzzSeeds, NoFindingWithinSeconds)
{
    std::ifstream in(GetParam(), std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    const auto t0 = std::chrono::steady_clock::now();
    const std::optional<std::string> finding = fuzz::fuzzDocument(bytes.str());
    EXPECT_FALSE(finding.has_value()) << GetParam() << ": " << finding.value_or("");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0 * KERF_TIME_FACTOR);
}

INSTANTIATE_TEST_SUITE_P(Files, FuzzSeeds, ::testing::ValuesIn(inputs()), [](const auto& param) {
    std::string name = param.param.parent_path().filename().string() + "_" + param.param.stem().string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
});

TEST(FuzzSeeds, ThereAreSeedsAndReproducers)
{
    int findings = 0;
    for (const auto& f : inputs()) findings += f.filename().string().rfind("finding-", 0) == 0;
    EXPECT_GE(inputs().size(), 20u);
    EXPECT_GE(findings, 1);
}

} // namespace
} // namespace kerf
