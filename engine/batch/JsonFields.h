// skelseg: the fields of a JSON file skelseg wrote, read with plain messages.
//
// A shard summary may be damaged, truncated or replaced by hand before a
// `batch --merge`. nlohmann::json's own exceptions then reached the user as
// "[json.exception.type_error.302] type must be number, but is string";
// JsonFields says what is wrong in the file's terms ("entry 2: 'wall_seconds'
// is not a number"). Every error is an InputError naming the file, its
// problem starting with the caller's prefix ("not a skelseg batch summary: ").
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace skelseg {

/// The JSON document in `file`. @throw InputError naming the file: not a
/// readable regular file ("is a directory, not a file"), or not JSON
/// ("`prefix`not JSON (syntax error at byte 12)").
nlohmann::json readJsonFile(const std::filesystem::path& file, const std::string& prefix);

/// One JSON object of a file, read field by field. Required fields throw
/// when missing or of another type; optional ones take their fallback when
/// missing and throw when of another type.
class JsonFields {
public:
    /// `place` names the object in messages: "" for the document itself,
    /// "entry 2: " for an item of a list. @throw InputError unless `value` is
    /// an object ("it is not a JSON object", "entry 2: it is not a JSON
    /// object").
    JsonFields(const nlohmann::json& value, std::string file, std::string prefix,
               std::string place = "");

    std::string text(const char* key) const;
    std::string text(const char* key, const std::string& fallback) const;
    /// An integer in int's range.
    int integer(const char* key) const;
    std::uint64_t count(const char* key, std::uint64_t fallback) const;
    double number(const char* key, double fallback) const;
    bool flag(const char* key, bool fallback) const;
    /// The object field `key`, its fields named "key.field".
    JsonFields object(const char* key) const;
    /// The array field `key`.
    const nlohmann::json& array(const char* key) const;
    /// The array of strings `key`.
    std::vector<std::string> texts(const char* key) const;
    /// Field `key` of any type.
    const nlohmann::json& any(const char* key) const;

private:
    const nlohmann::json& mValue;
    std::string mFile, mPrefix, mPlace;
    std::string mPath;  // before the field names: "shard." inside the field 'shard'

    JsonFields(const nlohmann::json& value, const JsonFields& parent, const char* key);

    /// The field, or nullptr when missing.
    const nlohmann::json* find(const char* key) const;
    const nlohmann::json& required(const char* key) const;
    [[noreturn]] void fail(const char* key, const std::string& problem) const;
};

}  // namespace skelseg
