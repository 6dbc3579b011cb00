#pragma once
// Our own reading of an IGES file's text (internal to aeroform_cad; no OpenCASCADE): the global
// section, the directory entries and every entity's parameters as the file writes them, so that
// values are parsed exactly (strtod, correctly rounded) and bad data is refused with the file and
// the entity named before OpenCASCADE sees it (its reader crashes or invents values on some).
#include <string>
#include <string_view>
#include <vector>

namespace aero::cad::iges {

struct Global {
    char parameterDelimiter = ',';
    char recordDelimiter = ';';
    std::vector<std::string> fields;  // parameters 1.. as written (strings without their nH)
    int unitFlag = 1;                 // parameter 14 (IGES default: 1, inches)
    std::string unitName;             // parameter 15 ("MM", "M", "INCH", ...)
    double modelScale = 1.0;          // parameter 13
    double resolution = 0.0;          // parameter 19
    int version = 0;                  // parameter 23
};

struct Entity {
    int de = 0;  // the directory entry's first line (odd): what pointers in the file refer to
    int type = 0;
    int form = 0;
    int transform = 0;  // DE of a transformation matrix (124), 0 for none
    int status = 0;     // 8 digits: blank, subordinate, entity use, hierarchy (2 digits each)
    std::string label;  // directory field 18, trimmed
    int subscript = 0;
    std::vector<std::string> params;  // parameters after the type, strings as their text

    int number() const { return (de + 1) / 2; }  // 1-based position among the entities
    int subordinate() const { return (status / 10000) % 100; }
};

struct File {
    std::string path;
    Global global;
    std::vector<Entity> entities;  // in directory order: entities[k].de == 2k + 1
    int column65Line = 0;          // the first parameter line with data in column 65, which
                                   // the standard keeps blank (0: none; see parse())

    /// The entity a pointer refers to, or nullptr (0, negative, even or past the end).
    const Entity* at(int de) const;
};

/// "entity 3 (type 128, directory line 5)": how every message names an entity.
std::string describe(const Entity& e);
std::string describe(int de, int type);

/// Parses the text of `path`. Throws InputError naming the file for a file that is not IGES
/// (no global section, compressed or binary form), a malformed directory entry, and naming the
/// entity for a geometric entity (types 100-199, 500-599) with a parameter that is not a
/// number.
File parse(const std::string& text, const std::string& path);

/// Numeric parameters of an entity (index 0 = the first parameter after the type). Throw
/// InputError naming the file, the entity and the parameter when missing or not of the kind.
/// real(): exact (the written decimal correctly rounded, D exponents accepted); an empty field is
/// the default 0. integer(): must be integral; pointer(): 0 or the DE of an entity in the file.
double real(const File& f, const Entity& e, std::size_t index);
int integer(const File& f, const Entity& e, std::size_t index);
int pointer(const File& f, const Entity& e, std::size_t index);

/// Checks an entity against its own counts and pointers before anything uses it: 128 and 126
/// (counts, degrees, data length, weights), 102, 110, 100, 124, 142, 144, 141, 143, 120, 118,
/// 108, 122, 140 and the B-rep entities 186, 514, 510, 508, 504, 502 (pointers refer to entities
/// of the file, counts match the data). Throws InputError naming the file and the entity.
void check(const File& f, const Entity& e);

/// The DEs an entity refers to as its geometry (surfaces of a trimmed surface, curves of a
/// composite, faces of a shell, ...): an entity referred to this way is part of its parent,
/// not something of its own. Empty for types whose pointers are not geometry.
std::vector<int> geometryChildren(const File& f, const Entity& e);

/// Throws InputError naming the file and an entity whose geometry pointers lead back to it.
void checkCycles(const File& f);

/// A short name of an entity type: "rational B-spline surface" for 128, ... ("entity type N"
/// for unknown ones).
std::string typeName(int type);

}  // namespace aero::cad::iges
