// Whitespace-separated fields of one text line and their strict conversion to numbers. Numbers go
// through std::from_chars (no locale, no iostreams); a token that is not entirely a finite decimal
// number is an InputError "<file>:<line>: <MESSAGE field[i]>: <problem> '<token>'".
#pragma once

#include <string_view>
#include <vector>

#include "io/files/line_reader.h"

namespace partslam::io {

/// Names a field for error messages: "FLASER range[17]", "relation yaw".
struct FieldName {
  std::string_view message;  ///< message or record kind, e.g. "FLASER"
  std::string_view field;    ///< field name, e.g. "range"
  long index = -1;           ///< element index for arrays, -1 for scalars
};

/// Splits line at spaces and tabs into out (cleared first); empty fields are not produced.
void split_fields(std::string_view line, std::vector<std::string_view>& out);

/// Parses a finite decimal number (an optional leading '+' is accepted); throws via reader.fail().
double parse_number(const LineReader& reader, std::string_view token, const FieldName& field);

/// Parses a non-negative integer no larger than max_value; throws via reader.fail().
long parse_count(const LineReader& reader, std::string_view token, const FieldName& field, long max_value);

/// Throws "<file>:<line>: <field>: <problem>".
[[noreturn]] void fail_field(const LineReader& reader, const FieldName& field, std::string_view problem);

}  // namespace partslam::io
