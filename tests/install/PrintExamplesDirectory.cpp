// Prints where the running program finds its bundled examples
// (kerf/app/InstalledResources.hpp), so that tests can copy it into an
// installed tree and see the lookup work from there.

#include "kerf/app/InstalledResources.hpp"

#include <iostream>

int main()
{
    std::cout << "examples: " << kerf::examplesDirectory().string() << "\n"
              << "default: " << kerf::defaultExample().string() << "\n";
    return 0;
}
