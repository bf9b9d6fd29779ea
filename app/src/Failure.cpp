#include "kerf/app/Failure.hpp"

#include "kerf/document/PrintableText.hpp"

#include <new>
#include <stdexcept>
#include <typeinfo>

namespace kerf {

std::string describeFailure(const std::exception& e)
{
    if (dynamic_cast<const std::bad_alloc*>(&e))
        return "ran out of memory: the request needs more than this machine has (choose a larger feature size or a "
               "smaller picture)";
    if (dynamic_cast<const std::length_error*>(&e))
        return "the request is too large for this program (choose a larger feature size or a smaller picture)";
    const std::string what = e.what();
    // An exception without a message of its own answers with its type name.
    if (what.empty() || what == typeid(e).name() || what.rfind("std::", 0) == 0)
        return "internal error: the work failed without a message";
    return printable(what, 600);
}

} // namespace kerf
