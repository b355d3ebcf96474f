#pragma once
// Checked numbers from a benchmark's command line. A value is the whole text, read with
// std::from_chars: no leading space or '+', no '-' for an unsigned type, nothing after the
// number, and a real must be finite. A value outside the flag's [lo, hi] is refused, never
// wrapped or clamped. Each message names the flag (or the positional argument), the text and
// the limit it crossed.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::bench {

template <typename T>
std::string flagNumberText(T value) {
    char text[40];
    return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

// `name` is the flag ("--spp") or the positional argument ("TRIANGLES") the text came from.
template <typename T>
Result<T> parseFlagNumber(const std::string& name, const std::string& text, T lo, T hi) {
    static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>);
    constexpr bool real = std::is_floating_point_v<T>;
    const char* kind = real ? "a finite number" : std::is_signed_v<T> ? "an integer" : "a whole number";
    const std::string said = name + ": " + text;
    const std::string range = "[" + flagNumberText(lo) + ", " + flagNumberText(hi) + "]";
    auto below = [&] { return Status::error(said + " is below the smallest " + flagNumberText(lo)); };
    auto above = [&] { return Status::error(said + " is above the largest " + flagNumberText(hi)); };
    T value{};
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    const bool whole = end == text.data() + text.size();
    // Integers beyond the type; reals too large or too small (1e-999) for it.
    if (error == std::errc::result_out_of_range && whole) {
        if (real)
            return Status::error(said + " is beyond a " + (sizeof(T) == 4 ? "float" : "double") +
                                 "'s range; give a number in " + range);
        return text[0] == '-' ? below() : above();
    }
    bool finite = true;
    if constexpr (real) finite = std::isfinite(value);
    if (error != std::errc() || !whole || !finite)
        return Status::error(name + ": \"" + text + "\" is not " + kind + " in " + range);
    if (value < lo) return below();
    if (value > hi) return above();
    return value;
}

// Values separated by `separator` ("4,16", "640x480"), each in [lo, hi]: exactly `count` of
// them, or with count 0 any number of them (none for an empty text).
template <typename T>
Result<std::vector<T>> parseFlagList(const std::string& name, const std::string& text, char separator, T lo,
                                     T hi, size_t count = 0) {
    std::vector<T> values;
    if (text.empty() && count == 0) return values;
    const size_t given = size_t(std::count(text.begin(), text.end(), separator)) + 1;
    if (count != 0 && given != count)
        return Status::error(name + ": \"" + text + "\" is not " + std::to_string(count) +
                             " numbers separated by '" + separator + "'");
    // An item's message quotes the whole list too.
    const std::string itemName = given > 1 ? name + " \"" + text + "\"" : name;
    for (size_t start = 0; start <= text.size();) {
        const size_t end = std::min(text.find(separator, start), text.size());
        auto value = parseFlagNumber(itemName, text.substr(start, end - start), lo, hi);
        if (!value) return value.status();
        values.push_back(*value);
        start = end + 1;
    }
    return values;
}

// A bench's own argument loop: the parsers above, a refused value printed as "PROGRAM: message"
// on stderr and the program ended with `status`, the bench's exit status for a usage error.
class FlagNumbers {
public:
    FlagNumbers(const char* program, int status) : program_(program), status_(status) {}

    template <typename T>
    T get(const std::string& flag, const std::string& text, T lo = std::numeric_limits<T>::lowest(),
          T hi = std::numeric_limits<T>::max()) const {
        return orExit(parseFlagNumber(flag, text, lo, hi));
    }
    template <typename T>
    std::vector<T> list(const std::string& flag, const std::string& text, char separator, T lo, T hi,
                        size_t count = 0) const {
        return orExit(parseFlagList(flag, text, separator, lo, hi, count));
    }

private:
    template <typename T>
    T orExit(Result<T> result) const {
        if (result) return std::move(result).value();
        std::fprintf(stderr, "%s: %s\n", program_, result.message().c_str());
        std::exit(status_);
    }

    const char* program_;
    int status_;
};

}  // namespace vastray::bench
