// skelseg: the options of `skelseg segment` (and `batch`), defined once.
//
// addSegmentOptions() declares every option other than the input and the
// output directory on a CLI11 command: its name, help, default, range and
// check. SegmentOptionTexts::finish() turns what was given into
// SegmentCommandOptions and refuses contradictions. The command line uses
// both; the Python module (engine/python/) parses its keywords through
// parseSegmentOptions(), the same definitions, so a value the CLI refuses is
// refused in Python with the same one-line message, and a new option is
// reachable from both (tests/python/test_options.py checks that every option
// has its keyword).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/SegmentCommand.h"

namespace CLI {
class App;
class Validator;
}  // namespace CLI

namespace skelseg {

/// The `segment` options as given; texts become options in finish().
struct SegmentOptionTexts {
    SegmentCommandOptions options;
    std::string tauText = "3%", modeText = "junction-rule", maxMemoryText, skeletonSearchText;
    std::string budgetCalibrationText = "probe";
    bool quiet = false, exhaustive = false, noGrownContactSeams = false;

    /// Turns the texts into options. @throw UsageError.
    void finish();
};

/// A --max-memory value ("4G", "512M", "300KB", a number of bytes) in bytes;
/// sizes past 2^64 bytes mean no limit. @throw UsageError naming --max-memory.
std::uint64_t parseMemoryLimit(const std::string& text);

/// Declares the options on `command`, bound to `texts`.
void addSegmentOptions(CLI::App* command, SegmentOptionTexts& texts);

/// One option as addSegmentOptions() declares it.
struct SegmentOptionDescription {
    std::string name;         // "--sigma-min"; a flag that clears a rule: "--no-stub-limbs"
    bool flag = false;        // takes no value; given means on
    std::string defaultText;  // the default as --help shows it ("" when none is shown)
    std::string help;
};

/// Every option of addSegmentOptions(), in declaration order.
std::vector<SegmentOptionDescription> segmentOptionDescriptions();

/// Of `given` (option names as the command line spells them), those that
/// apply only to the other kind of input: for a volume (isMesh false) the
/// mesh options (--resolution, --self-overlap-clearance, the contact seams,
/// --budget-calibration), for a mesh --keep-voxel-aspect. Such an option
/// changes nothing; a run names them in a warning instead of ignoring them
/// without a word. (--grid with a mesh is an error, as with other volumes.)
std::vector<std::string> optionsNotApplying(const std::vector<std::string>& given, bool isMesh);

/// The options given on `command` (count > 0), named "--" + their first
/// long name, as optionsNotApplying() takes them.
std::vector<std::string> givenOptionNames(const CLI::App& command);

/// The warning for `names` (optionsNotApplying) given with `input`.
std::string optionsNotApplyingWarning(const std::string& input,
                                      const std::vector<std::string>& names, bool isMesh);

/// Parses `arguments` ("--sigma-min", "0.5", "--joints", ...) as the
/// command line's options of `skelseg segment` and finishes them.
/// @throw UsageError with the command line's message, on one line.
SegmentCommandOptions parseSegmentOptions(const std::vector<std::string>& arguments);

/// Checks for a number option, placed before its CLI::Range: the range check
/// reads a text that is no number ("steep", or "12.5" for an integer) as out
/// of range and says "Value 12.5 not in range 8 to 2048", which is not the
/// problem; and it lets NaN through (every comparison with it is false).
CLI::Validator numberText();
CLI::Validator integerText();

/// Refuses an empty value, "the value is empty; give `wanted`": a job
/// script whose variable was unset passed "" and ran as if the option were
/// not given (--shard, --max-memory).
CLI::Validator nonEmptyValue(const std::string& wanted);

/// A CLI11 message on one line, as every error of skelseg is.
std::string oneLineMessage(std::string message);

}  // namespace skelseg
