#pragma once
// Self-describing options: one table per options struct, with each option's case-file key,
// description, unit, range (or choices) and a getter and setter. The case parser and writer,
// `aeroform-cli flow --help` and docs/case-file.md (generated rows, checked by a test) all read
// it, so an option is added in one place: one line of its table.
#include <array>
#include <functional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "io/CaseFile.h"

namespace aero::io {

enum class OptionKind { Number, Integer, Boolean, Choice, Point };

/// A value of any kind: Number (double), Integer (long), Boolean (bool), Choice (std::string),
/// Point (three doubles).
using OptionValue = std::variant<double, long, bool, std::string, std::array<double, 3>>;

struct OptionSpec {
    std::string key;          // the key in its case-file section, e.g. "kappa4"
    std::string description;  // one sentence or two for people
    std::string unit;         // "" when dimensionless
    OptionKind kind = OptionKind::Number;
    double lower = 0, upper = 0;               // Number and Integer: the allowed range ...
    bool lowerClosed = true, upperClosed = true;  // ... with its ends included or not
    std::vector<std::string> choices;          // Choice: the allowed names
    /// "[0, 1)", "(0, inf)", "entropy_conservative, central", "true, false", ...
    std::string range() const;
    /// range() followed by the unit, if any: "(-90, 90) degrees".
    std::string rangeWithUnit() const { return range() + (unit.empty() ? "" : " " + unit); }
    /// Empty if v is allowed, else why not ("value 2 outside [0, 1)").
    std::string check(const OptionValue& v) const;
};

template <class S>
struct Option {
    OptionSpec spec;
    std::function<OptionValue(const S&)> get;
    std::function<void(S&, const OptionValue&)> set;
};

/// The options of the case's "flow" section (without "restart", a path resolved against the
/// case file). Defaults are those of a default-constructed FlowCase.
const std::vector<Option<FlowCase>>& flowOptions();

/// The options of the case's "mesh" section, "level" first (it resets the others to the level's
/// values; the keys after it override them). Defaults are the coarse level's.
const std::vector<Option<MeshCase>>& meshOptions();

/// The options of the case's "optimization" section (without the paths "history" and
/// "iterations").
const std::vector<Option<OptimizationCase>>& optimizationOptions();

/// The option of `options` with this key; throws std::out_of_range for an unknown key (a
/// programming error: keys are fixed by the tables).
template <class S>
const Option<S>& findOption(const std::vector<Option<S>>& options, const std::string& key) {
    for (const auto& o : options) {
        if (o.spec.key == key) return o;
    }
    throw std::out_of_range("no option '" + key + "'");
}

/// A value as the case file and the documentation show it: 0.02, 300, true, "central", [0, 0, 0].
std::string formatOptionValue(const OptionValue& v);

/// The markdown rows "| `key` | default | range [unit] | description |" of the table in
/// docs/case-file.md, one per option, in the table's order.
template <class S>
std::vector<std::string> optionTableRows(const std::vector<Option<S>>& options) {
    std::vector<std::string> rows;
    const S defaults{};
    for (const auto& o : options) {
        rows.push_back("| `" + o.spec.key + "` | " + formatOptionValue(o.get(defaults)) + " | " + o.spec.rangeWithUnit() + " | " +
                       o.spec.description + " |");
    }
    return rows;
}

}  // namespace aero::io
