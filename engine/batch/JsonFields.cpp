#include "engine/batch/JsonFields.h"

#include <limits>
#include <utility>

#include "io/files/TextFile.h"
#include "kernels/base/Error.h"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace skelseg {

json readJsonFile(const fs::path& file, const std::string& prefix) {
    const std::string bytes = readFileBytes(file);
    try {
        return json::parse(bytes);
    } catch (const json::parse_error& error) {
        // nlohmann counts the bytes from 1, and one past the end at its end.
        if (error.byte > bytes.size())
            throw InputError(file.string(), prefix + "not JSON (it ends in the middle)");
        throw InputError(file.string(), prefix + "not JSON (syntax error at byte " +
                                            std::to_string(error.byte) + ")");
    }
}

JsonFields::JsonFields(const json& value, std::string file, std::string prefix, std::string place)
    : mValue(value), mFile(std::move(file)), mPrefix(std::move(prefix)), mPlace(std::move(place)) {
    if (!mValue.is_object()) throw InputError(mFile, mPrefix + mPlace + "it is not a JSON object");
}

JsonFields::JsonFields(const json& value, const JsonFields& parent, const char* key)
    : mValue(value),
      mFile(parent.mFile),
      mPrefix(parent.mPrefix),
      mPlace(parent.mPlace),
      mPath(parent.mPath + key + ".") {
    if (!mValue.is_object()) parent.fail(key, "is not a JSON object");
}

void JsonFields::fail(const char* key, const std::string& problem) const {
    throw InputError(mFile, mPrefix + mPlace + "'" + mPath + key + "' " + problem);
}

const json* JsonFields::find(const char* key) const {
    const auto it = mValue.find(key);
    return it == mValue.end() ? nullptr : &*it;
}

const json& JsonFields::required(const char* key) const {
    const json* value = find(key);
    if (!value) fail(key, "is missing");
    return *value;
}

std::string JsonFields::text(const char* key) const {
    const json& value = required(key);
    if (!value.is_string()) fail(key, "is not a string");
    return value.get<std::string>();
}

std::string JsonFields::text(const char* key, const std::string& fallback) const {
    return find(key) ? text(key) : fallback;
}

int JsonFields::integer(const char* key) const {
    const json& value = required(key);
    if (!value.is_number_integer()) fail(key, "is not an integer");
    if (value.is_number_unsigned()) {
        if (value.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<int>::max()))
            fail(key, "is out of range");
        return int(value.get<std::uint64_t>());
    }
    const auto number = value.get<std::int64_t>();
    if (number < std::numeric_limits<int>::min() || number > std::numeric_limits<int>::max())
        fail(key, "is out of range");
    return int(number);
}

std::uint64_t JsonFields::count(const char* key, std::uint64_t fallback) const {
    const json* value = find(key);
    if (!value) return fallback;
    if (value->is_number_unsigned()) return value->get<std::uint64_t>();
    if (value->is_number_integer() && value->get<std::int64_t>() >= 0)
        return std::uint64_t(value->get<std::int64_t>());
    fail(key, "is not a count (a whole number of at least 0)");
}

double JsonFields::number(const char* key, double fallback) const {
    const json* value = find(key);
    if (!value) return fallback;
    if (!value->is_number()) fail(key, "is not a number");
    return value->get<double>();
}

bool JsonFields::flag(const char* key, bool fallback) const {
    const json* value = find(key);
    if (!value) return fallback;
    if (!value->is_boolean()) fail(key, "is not true or false");
    return value->get<bool>();
}

JsonFields JsonFields::object(const char* key) const {
    return JsonFields(required(key), *this, key);
}

const json& JsonFields::array(const char* key) const {
    const json& value = required(key);
    if (!value.is_array()) fail(key, "is not a list");
    return value;
}

std::vector<std::string> JsonFields::texts(const char* key) const {
    const json& list = array(key);
    std::vector<std::string> result;
    result.reserve(list.size());
    for (const json& item : list) {
        if (!item.is_string())
            fail(key, "item " + std::to_string(result.size() + 1) + " is not a string");
        result.push_back(item.get<std::string>());
    }
    return result;
}

const json& JsonFields::any(const char* key) const {
    return required(key);
}

}  // namespace skelseg
