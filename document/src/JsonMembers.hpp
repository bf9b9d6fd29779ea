#pragma once
// Appends a member to a JSON object without ordered_json's search for the
// key (a linear scan per insertion: a million unknown fields would cost 10^12
// steps). Only for keys known not to be in the object yet: every object the
// loader builds has unique keys (BoundedJsonParser refuses repeats).

#include "kerf/document/Node.hpp"

namespace kerf::detail {

inline void appendMember(Json& object, const std::string& key, const Json& value)
{
    if (object.is_null()) object = Json::object();
    Json::object_t::Container& members = object.get_ref<Json::object_t&>();
    members.emplace_back(key, value);
}

} // namespace kerf::detail

namespace kerf {
using detail::appendMember;
}
