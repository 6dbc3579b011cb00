#pragma once
// Our own check of a STEP file's exchange structure (ISO 10303-21, "Part 21"), internal to
// aeroform_cad and without OpenCASCADE: OpenCASCADE's STEP loader dereferences a null entity on
// some malformed files (a header whose FILE_NAME swallowed FILE_SCHEMA, a parameter list with an
// empty element; both found by fuzz_step, docs/reliability.md) and the process dies with no
// message. So the text is checked first, and a file that is not well formed is refused with the
// file, the line and the entity named.
//
// What is checked (the syntax only, not the schema's entity types):
// - "ISO-10303-21;" first, one HEADER section, one or more DATA sections, "END-ISO-10303-21;"
//   last (a file that ends before it is named as truncated); the header's entities for syntax
//   only (OpenCASCADE reads files without FILE_NAME or FILE_SCHEMA; FILE_NAME's parameter count
//   it checks itself);
// - every data statement "#id = KEYWORD(...);" or a complex one "#id = (A(...) B(...));", with
//   each parameter a string, number, enumeration (.X.), binary ("..."), entity reference (#n), $,
//   *, a typed parameter KEYWORD(...) or a (possibly empty) list of parameters: no empty
//   element, balanced parentheses, strings and comments closed;
// - every entity id defined once, every reference to an id the file defines, and no cycle of
//   references (OpenCASCADE recursed along an oriented edge that was its own edge element until
//   the stack overflowed; found by fuzz_step).
#include <string>
#include <string_view>

namespace aero::cad::step {

/// Checks `text` (the contents of `path`); throws InputError naming `path`, the line and, inside
/// the data section, the entity id when it is not a well-formed exchange structure.
void checkExchangeStructure(std::string_view text, const std::string& path);

}  // namespace aero::cad::step
