// One definition per option field (issue 26): a *Options type's scalar fields described once — the
// library name, the SI unit, the valid range, the help text, and the names and units each surface
// gives it — so that Options::check(), the CLI's flags (registration, help, range check, display
// unit), the plan file's keys, the JSON echo and the Python keywords all derive from one table.
// docs/architecture.md ("Option fields") says which Options types have a table.
#pragma once

#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "toolpoint/plausibility.hpp"

namespace toolpoint {

/// \brief What kind of value an option field holds.
enum class FieldKind {
  Real,     ///< a double
  Integer,  ///< an int
  Flag      ///< a bool
};

/// \brief The description of one option field, independent of its Options type.
///
/// The range is in the field's own (SI) unit; `automatic` is a value outside it that means
/// "chosen by the library" (e.g. −1 lobes), accepted by check() but not by the plan file.
struct FieldSpec {
  const char* name = "";  ///< the field (Options::name): also its JSON key and Python keyword
  FieldKind kind = FieldKind::Real;
  const char* unit = "";  ///< SI unit of the value ("m"); "" dimensionless (a fraction or a count)
  double min = -std::numeric_limits<double>::infinity();        ///< smallest valid value [unit]
  double max = std::numeric_limits<double>::infinity();         ///< largest valid value [unit]
  bool min_open = false;                                        ///< min itself is invalid
  bool max_open = false;                                        ///< max itself is invalid
  double automatic = std::numeric_limits<double>::quiet_NaN();  ///< the value meaning "automatic" (NaN: none)
  const char* note = "";                                        ///< what the automatic value (or 0) means, e.g. "0: 17"
  const char* help = "";                                        ///< what the field is (CLI help, Python doc, plan messages)
  const char* cli_name = nullptr;  ///< the CLI's flag without its dashes ("max-depth"), nullptr: none
  const char* cli_unit = nullptr;  ///< the unit the CLI flag takes ("%", "mm"); nullptr: `unit`
  double cli_per_unit = 1.0;       ///< CLI value = field value × cli_per_unit (100 for %, 1000 for mm)
  const char* plan_key = nullptr;  ///< the key in the plan file's table of these options, or nullptr
  /// Where a value in another unit is likely (a length in mm given as m): its plausible range in the
  /// field's unit (plausibility.hpp). check_field refuses a nonzero value that cannot be meant; the
  /// plan file and the CLI flag judge it too, and warn where it is only unusual. nullptr: none.
  const PlausibleRange* plausible = nullptr;
};

/// \brief One field of `Options`: its description and where it lives (exactly one accessor set,
/// matching spec.kind).
template <class Options>
struct OptionField {
  FieldSpec spec;                       ///< the description
  double& (*real)(Options&) = nullptr;  ///< the field, for FieldKind::Real
  int& (*integer)(Options&) = nullptr;  ///< the field, for FieldKind::Integer
  bool& (*flag)(Options&) = nullptr;    ///< the field, for FieldKind::Flag

  /// \brief The field's value in `o`, as a double.
  /// \param o the options read
  /// \return the value [spec.unit]
  double get(const Options& o) const {
    Options& m = const_cast<Options&>(o);  // the accessors are shared by reading and writing
    return real ? real(m) : integer ? static_cast<double>(integer(m)) : (flag(m) ? 1.0 : 0.0);
  }
  /// \brief Sets the field in `o` (an integer field takes the value rounded toward zero; a flag
  /// is set for any nonzero value).
  /// \param o the options written
  /// \param value the value [spec.unit]
  void set(Options& o, double value) const {
    if (real) real(o) = value;
    else if (integer) integer(o) = static_cast<int>(value);
    else flag(o) = value != 0.0;
  }
};

/// \brief The CLI's flag of the field, "--" and its cli_name ("" where the CLI has none).
/// \param spec the field
/// \return the flag
std::string field_flag(const FieldSpec& spec);

/// \brief True if `value` [spec.unit] is valid for the field: in its range (an integer field: a
/// whole number) or its automatic value.
/// \param spec the field
/// \param value the value [spec.unit]
/// \return whether check() accepts it
bool field_value_valid(const FieldSpec& spec, double value);

/// \brief A value of the field as text: an integer field's in full, else as {:g}.
/// \param spec the field
/// \param value the value, in whatever unit it is shown
/// \return the text
std::string field_value_text(const FieldSpec& spec, double value);

/// \brief The field's valid range as text, in the field's unit times `scale`: "0…5000" for
/// integers or closed ranges, "(0, 1)" or "[0, 1)" with an open end, "≥ 0" without an upper end.
/// \param spec the field
/// \param scale the factor to the unit shown (spec.cli_per_unit for the CLI's)
/// \return the range text
std::string field_range_text(const FieldSpec& spec, double scale = 1.0);

/// \brief A valid value, for a fix: "in 0…5000", "≥ 0" (after "give X a value").
/// \param spec the field
/// \param scale the factor to the unit shown
/// \return the phrase
std::string field_range_value(const FieldSpec& spec, double scale = 1.0);

/// \brief What a valid value must be, for a message: "must lie in 0…5000", "must be ≥ 0".
/// \param spec the field
/// \param scale the factor to the unit shown
/// \return the phrase
std::string field_range_phrase(const FieldSpec& spec, double scale = 1.0);

/// \brief The plausibility of a valid value of the field in its unit (spec.plausible): Usual where
/// the field has no plausible range, and for 0, the automatic value and values out of the field's
/// range (those are the range check's), which are the field's own words, not magnitudes.
/// \param spec the field
/// \param value the value [spec.unit]
/// \return the verdict check_field, the CLI's flags, the plan file and the warnings share
Plausibility field_plausibility(const FieldSpec& spec, double value);

/// \brief Throws InvalidArgument naming `Options::field` if `value` is not valid for the field, or
/// if it is nonzero, not the automatic value and cannot be meant in the field's unit (spec.plausible:
/// a spin of 150 "rpm" that is rad/s, a power of 15 "W" that is kW).
/// \param spec the field
/// \param value the value [spec.unit]
/// \param options the Options type's name, e.g. "LobesStudyOptions"
void check_field(const FieldSpec& spec, double value, std::string_view options);

/// \brief The named field of a table.
/// \param fields the Options type's table
/// \param name the field's name (spec.name)
/// \return the field; std::logic_error if the table has none (a programming error)
template <class Options>
const OptionField<Options>& option_field(const std::vector<OptionField<Options>>& fields, std::string_view name) {
  for (const OptionField<Options>& f : fields)
    if (name == f.spec.name) return f;
  throw std::logic_error("no option field '" + std::string(name) + "'");
}

/// \brief A field's description under another help text: the same field (range, unit, flag) as
/// another Options type's, described in this type's words.
/// \param spec the field
/// \param help the help text
/// \return spec with `help`
inline FieldSpec with_help(FieldSpec spec, const char* help) {
  spec.help = help;
  return spec;
}

/// \brief check_field for every field of `fields` in `o`, in the table's order.
/// \param fields the Options type's table
/// \param o the options checked
/// \param options the Options type's name
template <class Options>
void check_fields(const std::vector<OptionField<Options>>& fields, const Options& o, std::string_view options) {
  for (const OptionField<Options>& f : fields) check_field(f.spec, f.get(o), options);
}

/// \brief What the result says of `o`'s unusual values: for each field with a plausible range
/// (spec.plausible) whose value is nonzero, not automatic and unusual in its unit, the message
/// naming `Options::field` (a value that cannot be meant is check()'s to refuse).
/// \param fields the Options type's table
/// \param o the options judged
/// \param options the Options type's name
/// \return the warnings, in the table's order
template <class Options>
std::vector<std::string> field_plausibility_warnings(const std::vector<OptionField<Options>>& fields, const Options& o,
                                                     std::string_view options) {
  std::vector<std::string> warnings;
  for (const OptionField<Options>& f : fields) {
    const double v = f.get(o);
    if (field_plausibility(f.spec, v) == Plausibility::Unusual)
      warnings.push_back(plausibility_message(*f.spec.plausible, v, std::string(options) + "::" + f.spec.name));
  }
  return warnings;
}

}  // namespace toolpoint
