#pragma once
// The one table from the library's option names (engine/options.h, bake/bake.h) to the exao
// program's flags: library errors name options ("samples: must be ..."), and the program prints
// them with its flags ("exao: --samples: must be ...").

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"

namespace exao::cli {

/// Flags that stand for an option in one command only, e.g. {"method", "--compare"} for the
/// second engine of `exao bake --compare`.
using FlagOverrides = std::vector<std::pair<std::string_view, std::string_view>>;

/// The message with its leading "option:" replaced by the option's flag; unchanged when it
/// does not start with an option's name.
[[nodiscard]] std::string with_flags(const std::string& message, const FlagOverrides& overrides = {});

/// Prints "exao: <message, with flags>" on stderr and returns the exit status for bad input.
int report(const Error& error, const FlagOverrides& overrides = {});

}  // namespace exao::cli
