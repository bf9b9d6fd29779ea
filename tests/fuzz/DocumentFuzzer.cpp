// libFuzzer entry over the document loader and everything done with a loaded
// document (FuzzDocument.cpp). Built by -DKERF_FUZZ=ON with clang, ASan and
// UBSan; run by tools/fuzz.sh.

#include "FuzzDocument.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    try {
        if (const auto finding = kerf::fuzz::fuzzDocument(std::string_view(reinterpret_cast<const char*>(data), size))) {
            std::fprintf(stderr, "kerf fuzz finding: %s\n", finding->c_str());
            std::abort();
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "kerf fuzz finding: an exception escaped: %s\n", e.what());
        std::abort();
    }
    return 0;
}
