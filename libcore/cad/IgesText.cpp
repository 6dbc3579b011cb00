// Our own reading of an IGES file's text (see IgesText.h). Fixed format: 80 columns, the section
// letter in column 73; parameter data in columns 1-64 with the owning directory entry in 65-72.
#include "cad/IgesText.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>

#include "common/Error.h"

namespace aero::cad::iges {

namespace {

std::string quoted(const std::string& path) {
    return "'" + path + "'";
}

[[noreturn]] void failFile(const std::string& path, const std::string& why) {
    throw InputError("IGES file " + quoted(path) + ": " + why);
}

[[noreturn]] void failEntity(const File& f, const Entity& e, const std::string& why) {
    failFile(f.path, describe(e) + ": " + why);
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

/// A parameter that is not a string: empty (default value), integer or real, with an optional
/// E or D exponent.
bool isNumber(std::string_view t) {
    auto digit = [&](std::size_t i) {
        return i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]));
    };
    std::size_t i = 0, digits = 0;
    if (t.empty()) return true;
    if (t[i] == '+' || t[i] == '-') ++i;
    for (; digit(i); ++i) ++digits;
    if (i < t.size() && t[i] == '.')
        for (++i; digit(i); ++i) ++digits;
    if (digits == 0) return false;
    if (i < t.size() && std::strchr("EeDd", t[i])) {
        ++i;
        if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
        if (!digit(i)) return false;
        while (digit(i)) ++i;
    }
    return i == t.size();
}

constexpr std::size_t kDataColumns = 64;  // a parameter line's data: columns 1-64

struct Token {
    std::string text;
    bool string = false;  // a Hollerith string (text without its nH)
    std::size_t begin = 0, end = 0;  // a parameter's trimmed text in the data (not strings)
};

/// Splits free-format data into parameters up to the record delimiter (what follows it is a
/// comment). Hollerith strings (nHxxx) may contain the delimiters.
std::vector<Token> tokenize(std::string_view s, char pd, char rd) {
    std::vector<Token> out;
    for (std::size_t i = 0; i < s.size();) {
        std::size_t start = i;
        while (start < s.size() && s[start] == ' ') ++start;
        std::size_t h = start;
        while (h < s.size() && std::isdigit(static_cast<unsigned char>(s[h]))) ++h;
        std::size_t end;
        Token t;
        if (h > start && h < s.size() && (s[h] == 'H' || s[h] == 'h')) {
            std::size_t length = 0;
            for (std::size_t d = start; d < h; ++d)
                length = std::min<std::size_t>(10 * length + (s[d] - '0'), s.size());
            const std::size_t textEnd = std::min(s.size(), h + 1 + length);
            t.text = std::string(s.substr(h + 1, textEnd - h - 1));
            t.string = true;
            end = textEnd;
            while (end < s.size() && s[end] != pd && s[end] != rd) ++end;
        } else {
            end = std::min(s.find(pd, i), s.find(rd, i));
            if (end == std::string_view::npos) end = s.size();
            const std::string_view raw = s.substr(i, end - i);
            const std::string_view trimmed = trim(raw);
            t.text = std::string(trimmed);
            t.begin = i + (trimmed.empty() ? 0 : static_cast<std::size_t>(trimmed.data() - raw.data()));
            t.end = t.begin + trimmed.size();
        }
        out.push_back(std::move(t));
        if (end >= s.size() || s[end] == rd) break;
        i = end + 1;
        if (i == s.size()) out.push_back({});  // "...,": an empty last parameter before the end
    }
    return out;
}

int fieldInt(const std::string& line, int field, bool& ok) {
    const std::string_view f =
        trim(std::string_view(line).substr(static_cast<std::size_t>(8 * field), 8));
    if (f.empty()) return 0;
    int value = 0;
    bool negative = false;
    std::size_t i = 0;
    if (f[0] == '-' || f[0] == '+') {
        negative = f[0] == '-';
        i = 1;
    }
    if (i == f.size()) ok = false;
    for (; i < f.size(); ++i) {
        if (!std::isdigit(static_cast<unsigned char>(f[i]))) {
            ok = false;
            return 0;
        }
        value = 10 * value + (f[i] - '0');
    }
    return negative ? -value : value;
}

bool geometric(int type) {
    return (type >= 100 && type < 200) || (type >= 500 && type < 600);
}

double parseNumber(std::string_view token, bool& finite) {
    std::string s(token);
    for (char& c : s)
        if (c == 'D' || c == 'd') c = 'E';  // Fortran double exponent
    if (s.empty()) {
        finite = true;
        return 0.0;
    }
    errno = 0;
    const double v = std::strtod(s.c_str(), nullptr);
    finite = std::isfinite(v);
    return v;
}

std::string parameterName(std::size_t index) {
    return "parameter " + std::to_string(index + 1);
}

constexpr double kLargestValue = 1e15;

}  // namespace

const Entity* File::at(int de) const {
    if (de <= 0 || de % 2 == 0) return nullptr;
    const std::size_t k = static_cast<std::size_t>(de / 2);
    return k < entities.size() ? &entities[k] : nullptr;
}

std::string describe(int de, int type) {
    return "entity " + std::to_string((de + 1) / 2) + " (type " + std::to_string(type) +
           ", directory line " + std::to_string(de) + ")";
}

std::string describe(const Entity& e) {
    return describe(e.de, e.type);
}

File parse(const std::string& text, const std::string& path) {
    File f;
    f.path = path;
    std::string global;
    std::vector<std::string> directory;
    std::map<int, std::string> data;  // directory entry -> its parameter data (columns 1-64, or 1-65)
    struct Lines {
        int first = 0, last = 0;           // positions in the parameter section, 1-based
        std::vector<std::size_t> starts;   // where each line's data begins in the entity's data
        int count() const { return static_cast<int>(starts.size()); }
    };
    std::map<int, Lines> dataLines;  // directory entry -> the parameter lines that name it
    int parameterLine = 0;
    std::istringstream lines(text);
    int lineNumber = 0;
    bool sawRecord = false;   // a line with an IGES section letter in column 73
    bool terminated = false;  // the terminate (T) record has been read
    for (std::string line; std::getline(lines, line);) {
        ++lineNumber;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        // IGES is ASCII; OpenCASCADE's reader of the text crashes on some other bytes (found by
        // fuzz_iges, tests/fuzz).
        for (std::size_t c = 0; c < line.size(); ++c)
            if (static_cast<unsigned char>(line[c]) >= 0x80) {
                char hex[8];
                std::snprintf(hex, sizeof hex, "0x%02X", static_cast<unsigned char>(line[c]));
                failFile(path, "line " + std::to_string(lineNumber) + ", column " +
                                   std::to_string(c + 1) + ": byte " + hex +
                                   " is not ASCII (IGES files are ASCII text)");
            }
        // Records are 80 columns; a longer line has its section letter elsewhere than column 73
        // for OpenCASCADE than for us (it then crashed on such a file; found by fuzz_iges).
        if (line.size() > 80 && line.find_first_not_of(' ', 80) != std::string::npos)
            failFile(path, "line " + std::to_string(lineNumber) + " is longer than 80 columns (" +
                               std::to_string(line.size()) + ")");
        // A shorter line has no section letter; OpenCASCADE's reader joined such lines into the
        // global section differently from us and crashed later, reading a B-spline surface's
        // parameters (found by fuzz_iges, tests/fuzz).
        if (line.size() < 73) {
            // Blank lines, and whatever follows the terminate record (an old DOS end-of-file
            // byte), are skipped.
            if (line.find_first_not_of(" \t") == std::string::npos || terminated) continue;
            if (!sawRecord)  // a text or JSON file given as IGES
                throw InputError(quoted(path) + " is not an IGES file (line " + std::to_string(lineNumber) +
                                 " is not an 80-column IGES record)");
            failFile(path, "line " + std::to_string(lineNumber) + " is " + std::to_string(line.size()) +
                               " columns long: IGES records are 80 columns with the section letter in "
                               "column 73 (a line broken or cut short?)");
        }
        const char section = line[72];
        sawRecord = sawRecord || section == 'S' || section == 'G' || section == 'D' || section == 'P' || section == 'T';
        terminated = terminated || section == 'T';
        if (lineNumber == 1 && (section == 'B' || section == 'C'))
            failFile(path, std::string(section == 'B' ? "binary" : "compressed") +
                               " IGES is not supported (write the file in the fixed ASCII form)");
        if (section == 'G') global.append(line, 0, 72);
        if (section == 'D') {
            // OpenCASCADE finds directory entries by these numbers, not by position: a
            // repeated number made it read another entity's entry and crash on a face's loop, a
            // missing one drop a face (found by fuzz_iges, tests/fuzz).
            const std::size_t expected = directory.size() + 1;
            const std::string_view number =
                trim(std::string_view(line).substr(73, std::min<std::size_t>(line.size() - 73, 7)));
            const bool digits = !number.empty() && number.find_first_not_of("0123456789") == std::string_view::npos;
            if (!digits || std::stoul(std::string(number)) != expected)  // at most 7 digits
                failFile(path, "line " + std::to_string(lineNumber) + ": directory line " +
                                   std::to_string(expected) +
                                   (number.empty() ? std::string(" has no sequence number")
                                                   : " is numbered '" + std::string(number) + "'") +
                                   " in columns 74-80; the directory section's lines must be numbered 1, "
                                   "2, 3, ... in order");
            directory.push_back(line.size() < 80 ? line + std::string(80 - line.size(), ' ')
                                                 : line);
        }
        if (section == 'P') {
            // The directory entry pointer is in columns 66-72 and column 65 is blank. Some writers
            // (pyGeo's, for one) fill all 65 columns with data, the record's last delimiter in
            // column 65: a character there other than a digit is data. A digit there belongs to a
            // pointer written in columns 65-72 (left-aligned, or of eight digits), read as before.
            const bool digit65 = std::isdigit(static_cast<unsigned char>(line[kDataColumns])) != 0;
            bool ok = !digit65;
            int de = digit65 ? 0 : fieldInt(line.substr(kDataColumns + 1, 7), 0, ok);  // columns 66-72
            std::size_t columns = kDataColumns;
            if (ok && de > 0) {
                if (line[kDataColumns] != ' ') {
                    columns = kDataColumns + 1;
                    if (f.column65Line == 0) f.column65Line = lineNumber;
                }
            } else {
                ok = true;
                de = fieldInt(line, 8, ok);  // columns 65-72
            }
            if (!ok || de <= 0)
                failFile(path, "line " + std::to_string(lineNumber) +
                                   ": parameter data without its directory entry pointer in columns 66-72 ('" +
                                   line.substr(kDataColumns, 8) + "' in columns 65-72)");
            Lines& l = dataLines[de];
            l.starts.push_back(data[de].size());
            data[de].append(line, 0, columns);
            ++parameterLine;
            if (l.count() == 1) l.first = parameterLine;
            l.last = parameterLine;
        }
    }
    if (global.empty()) throw InputError(quoted(path) + " is not an IGES file (no global section)");

    // Delimiters: the first two global parameters, each empty (default) or "1Hx".
    char pd = ',', rd = ';';
    std::size_t at = 0;
    if (global.compare(0, 2, "1H") == 0 && global.size() > 2) {
        pd = global[2];
        at = 3;
    }
    if (at < global.size() && global[at] == pd) ++at;
    if (global.compare(at, 2, "1H") == 0 && global.size() > at + 2) rd = global[at + 2];
    f.global.parameterDelimiter = pd;
    f.global.recordDelimiter = rd;
    for (const Token& t : tokenize(global, pd, rd)) f.global.fields.push_back(t.text);
    auto globalNumber = [&](std::size_t index, double fallback) {
        if (index >= f.global.fields.size() || trim(f.global.fields[index]).empty())
            return fallback;
        if (!isNumber(f.global.fields[index]))
            failFile(path, "global parameter " + std::to_string(index + 1) + " is not a number: '" +
                               f.global.fields[index] + "'");
        bool finite = true;
        const double v = parseNumber(f.global.fields[index], finite);
        if (!finite)
            failFile(path, "global parameter " + std::to_string(index + 1) + " is not finite");
        return v;
    };
    f.global.modelScale = globalNumber(12, 1.0);
    const double flag = globalNumber(13, 1.0);
    if (flag != std::floor(flag) || flag < 1 || flag > 11)
        failFile(path, "global parameter 14 (unit flag) is " + f.global.fields[13] +
                           ", not an IGES unit flag (1-11)");
    f.global.unitFlag = static_cast<int>(flag);
    if (f.global.fields.size() > 14) f.global.unitName = std::string(trim(f.global.fields[14]));
    f.global.resolution = globalNumber(18, 0.0);
    const double version = globalNumber(22, 0.0);
    if (version != std::floor(version) || version < 0 || version > 99)
        failFile(path, "global parameter 23 (IGES version) is " + f.global.fields[22] +
                           ", not a version number (an integer, 1-11 in IGES 5.3)");
    f.global.version = static_cast<int>(version);

    if (directory.size() % 2 != 0)
        failFile(path, "the directory section has an odd number of lines");
    f.entities.reserve(directory.size() / 2);
    for (std::size_t k = 0; k < directory.size(); k += 2) {
        const std::string& a = directory[k];
        const std::string& b = directory[k + 1];
        Entity e;
        e.de = static_cast<int>(k) + 1;
        bool ok = true;
        e.type = fieldInt(a, 0, ok);
        const int type2 = fieldInt(b, 0, ok);
        e.transform = fieldInt(a, 6, ok);
        e.status = fieldInt(a, 8, ok);
        e.form = fieldInt(b, 4, ok);
        e.subscript = fieldInt(b, 8, ok);
        e.label = std::string(trim(std::string_view(b).substr(56, 8)));
        if (!ok || e.type != type2 || e.type <= 0)
            failFile(path,
                     "directory entry at directory line " + std::to_string(e.de) +
                         " is malformed (fields are 8-column integers; both lines name the type)");
        if (e.transform < 0 ||
            (e.transform > 0 &&
             (e.transform % 2 == 0 || e.transform > static_cast<int>(directory.size()))))
            failFile(path, describe(e) + ": transformation matrix pointer " +
                               std::to_string(e.transform) +
                               " does not point to a directory entry");
        f.entities.push_back(std::move(e));
    }

    for (Entity& e : f.entities) {
        auto it = data.find(e.de);
        if (it == data.end()) {
            if (geometric(e.type)) failEntity(f, e, "has no parameter data");
            continue;
        }
        // OpenCASCADE finds an entity's parameters through the directory entry's pointer and line
        // count, we through the lines' back pointers: both must name the same lines, or
        // OpenCASCADE reads other data than we checked (it crashed on such a file, found by
        // fuzz_iges, tests/fuzz).
        {
            const Lines& l = dataLines[e.de];
            bool ok = true;
            const int pointer = fieldInt(directory[static_cast<std::size_t>(e.de - 1)], 1, ok);
            const int count = fieldInt(directory[static_cast<std::size_t>(e.de)], 3, ok);
            if (!ok || pointer != l.first || count != l.count() || l.last - l.first + 1 != l.count())
                failEntity(f, e,
                           "its directory entry puts its parameter data on " +
                               std::to_string(count) + " line(s) from parameter line " +
                               std::to_string(pointer) + ", but the lines that name it are " +
                               std::to_string(l.count()) + " from line " +
                               std::to_string(l.first) + " to " + std::to_string(l.last));
        }
        const std::vector<Token> tokens = tokenize(it->second, pd, rd);
        const int written =
            tokens.empty() || tokens[0].string ? -1 : std::atoi(tokens[0].text.c_str());
        if (written != e.type)
            failEntity(f, e,
                       "its parameter data starts with type '" +
                           (tokens.empty() ? std::string() : tokens[0].text) + "'");
        for (std::size_t i = 0; i < tokens.size(); ++i) {
            // A parameter other than a string that runs on across a line's end ("27, +" then
            // "19,") is one parameter for us and two for OpenCASCADE, whose later parameters then
            // shift (a crash in its B-rep transfer; found by fuzz_iges).
            const Token& t = tokens[i];
            const std::vector<std::size_t>& starts = dataLines[e.de].starts;
            auto lineOf = [&](std::size_t pos) {
                return static_cast<std::size_t>(std::upper_bound(starts.begin(), starts.end(), pos) -
                                                starts.begin()) - 1;
            };
            const std::size_t firstLine = lineOf(t.begin);
            if (!t.string && t.end > t.begin && firstLine != lineOf(t.end - 1))
                failEntity(f, e,
                           (i == 0 ? std::string("its type") : parameterName(i - 1)) + " ('" + t.text +
                               "') runs across the end of its parameter line " +
                               std::to_string(dataLines[e.de].first + static_cast<int>(firstLine)) +
                               ": only strings may continue on the next line");
        }
        for (std::size_t i = 1; i < tokens.size(); ++i) {
            if (geometric(e.type) && !tokens[i].string) {
                if (!isNumber(tokens[i].text))
                    failEntity(f, e,
                               parameterName(i - 1) + " is not a number: '" + tokens[i].text + "'");
                // No geometry needs more than 15 orders of magnitude; such values are corrupt
                // data, and OpenCASCADE's algorithms can run without end on them (a line's end
                // point of 1.57E+8700, beyond double precision, hung its trimming: found by
                // fuzz_iges).
                bool finite = true;
                const double v = parseNumber(tokens[i].text, finite);
                if (!finite)
                    failEntity(f, e,
                               parameterName(i - 1) + " is " + tokens[i].text +
                                   ": not a finite number (beyond the range of double precision)");
                if (std::abs(v) > kLargestValue)
                    failEntity(f, e,
                               parameterName(i - 1) + " is " + tokens[i].text +
                                   ": larger in magnitude than 1e15");
            }
            e.params.push_back(tokens[i].text);
        }
    }
    return f;
}

double real(const File& f, const Entity& e, std::size_t index) {
    if (index >= e.params.size())
        failEntity(f, e,
                   "has only " + std::to_string(e.params.size()) + " parameters, " +
                       parameterName(index) + " is missing");
    const std::string& t = e.params[index];
    if (!isNumber(t)) failEntity(f, e, parameterName(index) + " is not a number: '" + t + "'");
    bool finite = true;
    const double v = parseNumber(t, finite);
    if (!finite) failEntity(f, e, parameterName(index) + " is " + t + ": not a finite number");
    return v;
}

int integer(const File& f, const Entity& e, std::size_t index) {
    const double v = real(f, e, index);
    if (v != std::floor(v) || std::abs(v) > 2e9)
        failEntity(f, e, parameterName(index) + " is " + e.params[index] + ", not an integer");
    return static_cast<int>(v);
}

int pointer(const File& f, const Entity& e, std::size_t index) {
    const int de = integer(f, e, index);
    if (de != 0 && !f.at(std::abs(de)))
        failEntity(f, e,
                   parameterName(index) + " = " + std::to_string(de) +
                       " does not point to a directory entry of the file (" +
                       std::to_string(f.entities.size()) + " entities)");
    return de;
}

namespace {

/// The knot vector of `count` values from parameter `first`: non-decreasing, a non-empty range,
/// no knot repeated more than degree + 1 times (OpenCASCADE's reader crashes on such data in
/// B-rep loops). Throws GeometryError naming the entity.
void checkKnots(const File& f, const Entity& e, std::size_t first, std::size_t count, int degree,
                const char* which, const char* what) {
    double previous = 0;
    int run = 0;
    for (std::size_t k = 0; k < count; ++k) {
        const double t = real(f, e, first + k);
        run = (k > 0 && t == previous) ? run + 1 : 1;
        if ((k > 0 && t < previous) || run > degree + 1)
            throw GeometryError(
                "IGES file '" + f.path + "': " + describe(e) + " is not a valid " + what +
                ": its " + which + "knot vector " +
                (t < previous ? "decreases" : "repeats a knot more than degree + 1 times") +
                " at knot " + std::to_string(k + 1) + " (parameter " +
                std::to_string(first + k + 1) + ")");
        previous = t;
    }
    if (!(real(f, e, first + count - 1) > real(f, e, first)))
        throw GeometryError("IGES file '" + f.path + "': " + describe(e) + " is not a valid " +
                            what + ": its " + which + "knot vector has an empty range");
}

/// Entity 128 (issue #20: counts or degrees that did not match the data crashed OpenCASCADE's
/// reader; weights of 0, -1 or 1e-300 became a polynomial surface without a word).
void checkSurface128(const File& f, const Entity& e) {
    const auto& p = e.params;
    auto fail = [&](const std::string& why) { failEntity(f, e, why); };
    if (p.size() < 9)
        fail("only " + std::to_string(p.size() + 1) +
             " parameters (a B-spline surface has at least 10 before its data)");
    const double K1 = real(f, e, 0), K2 = real(f, e, 1), M1 = real(f, e, 2), M2 = real(f, e, 3);
    for (double v : {K1, K2, M1, M2})
        if (v != std::floor(v) || v < 0)
            fail("the counts and degrees (K1 K2 M1 M2 = " + p[0] + " " + p[1] + " " + p[2] + " " +
                 p[3] + ") must be non-negative integers");
    if (M1 < 1 || M2 < 1 || M1 > 25 || M2 > 25)
        fail("degrees " + p[2] + ", " + p[3] + " outside [1, 25]");
    if (K1 < M1 || K2 < M2 || K1 > 1e5 || K2 > 1e5)
        fail("upper indices K1 = " + p[0] + ", K2 = " + p[1] +
             " must lie in [degree, 100000] (K + 1 control points per direction)");
    const double nu = K1 + 1, nv = K2 + 1;
    if (nu * nv > 1e7)
        fail(std::to_string(static_cast<long>(nu * nv)) +
             " control points: more than the 10 million accepted");
    const double knotsU = K1 + M1 + 2, knotsV = K2 + M2 + 2;
    const double needed = 10 + knotsU + knotsV + 4 * nu * nv + 4;
    if (static_cast<double>(p.size() + 1) < needed)
        fail("K1 = " + p[0] + ", K2 = " + p[1] + ", M1 = " + p[2] + ", M2 = " + p[3] + " need " +
             std::to_string(static_cast<long>(needed)) +
             " parameters (knots, weights, points, parameter range), the entity has " +
             std::to_string(p.size() + 1));
    for (int k = 4; k < 9; ++k) {
        const double flag = real(f, e, static_cast<std::size_t>(k));
        if (flag != 0 && flag != 1)
            fail(parameterName(static_cast<std::size_t>(k)) + " (a property flag) is " +
                 p[static_cast<std::size_t>(k)] + ", not 0 or 1");
    }
    const std::size_t w0 = 9 + static_cast<std::size_t>(knotsU + knotsV);
    for (std::size_t k = 0; k < static_cast<std::size_t>(nu * nv); ++k) {
        const double w = real(f, e, w0 + k);
        if (!(w >= 1e-100))
            fail("weight " + std::to_string(k + 1) + " is " + p[w0 + k] +
                 " (weights must be positive and not vanishingly small)");
    }
    for (std::size_t k = 0; k < static_cast<std::size_t>(needed) - 1; ++k)
        (void)real(f, e, k);  // every value finite
    checkKnots(f, e, 9, static_cast<std::size_t>(knotsU), static_cast<int>(M1), "u ",
               "B-spline surface");
    checkKnots(f, e, 9 + static_cast<std::size_t>(knotsU), static_cast<std::size_t>(knotsV),
               static_cast<int>(M2), "v ", "B-spline surface");
}

/// Entity 126 (rational B-spline curve), the same checks.
void checkCurve126(const File& f, const Entity& e) {
    const auto& p = e.params;
    auto fail = [&](const std::string& why) { failEntity(f, e, why); };
    if (p.size() < 6)
        fail("only " + std::to_string(p.size() + 1) +
             " parameters (a B-spline curve has at least 7 before its data)");
    const double K = real(f, e, 0), M = real(f, e, 1);
    if (K != std::floor(K) || M != std::floor(M) || K < 0 || M < 0)
        fail("the count and degree (K M = " + p[0] + " " + p[1] +
             ") must be non-negative integers");
    if (M < 1 || M > 25) fail("degree " + p[1] + " outside [1, 25]");
    if (K < M || K > 1e6)
        fail("upper index K = " + p[0] + " must lie in [degree, 1000000] (K + 1 control points)");
    const double n = K + 1, knots = K + M + 2;
    const double needed = 7 + knots + 4 * n + 2;
    if (static_cast<double>(p.size() + 1) < needed)
        fail("K = " + p[0] + ", M = " + p[1] + " need " +
             std::to_string(static_cast<long>(needed)) +
             " parameters (knots, weights, points, parameter range), the entity has " +
             std::to_string(p.size() + 1));
    const std::size_t w0 = 6 + static_cast<std::size_t>(knots);
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) {
        const double w = real(f, e, w0 + k);
        if (!(w >= 1e-100))
            fail("weight " + std::to_string(k + 1) + " is " + p[w0 + k] +
                 " (weights must be positive and not vanishingly small)");
    }
    for (std::size_t k = 0; k < static_cast<std::size_t>(needed) - 1; ++k) (void)real(f, e, k);
    checkKnots(f, e, 6, static_cast<std::size_t>(knots), static_cast<int>(M), "", "B-spline curve");
    // All control points the same: a curve of zero length.
    const std::size_t p0 = w0 + static_cast<std::size_t>(n);
    bool moves = false;
    for (std::size_t k = 1; k < static_cast<std::size_t>(n) && !moves; ++k)
        for (std::size_t d = 0; d < 3; ++d)
            moves = moves || real(f, e, p0 + 3 * k + d) != real(f, e, p0 + d);
    if (!moves) fail("all its control points are the same point: a curve of zero length");
    const double v0 = real(f, e, p0 + 3 * static_cast<std::size_t>(n)),
                 v1 = real(f, e, p0 + 3 * static_cast<std::size_t>(n) + 1);
    if (!(v0 < v1))
        fail("its parameter range [" + p[p0 + 3 * static_cast<std::size_t>(n)] + ", " +
             p[p0 + 3 * static_cast<std::size_t>(n) + 1] + "] is empty");
}

void needCount(const File& f, const Entity& e, std::size_t count, const char* what) {
    if (e.params.size() < count)
        failEntity(f, e,
                   "has " + std::to_string(e.params.size()) + " parameters after its type, a " +
                       what + " needs " + std::to_string(count));
}

/// A count parameter in [least, limit] (OpenCASCADE's entity readers crash on some empty lists).
int count(const File& f, const Entity& e, std::size_t index, int limit, int least = 0) {
    const int n = integer(f, e, index);
    if (n < least || n > limit)
        failEntity(f, e,
                   parameterName(index) + " (a count) is " + e.params[index] + ", outside [" +
                       std::to_string(least) + ", " + std::to_string(limit) + "]");
    return n;
}

int nonNull(const File& f, const Entity& e, std::size_t index) {
    const int de = pointer(f, e, index);
    if (de <= 0)
        failEntity(f, e,
                   parameterName(index) + " must point to an entity, it is " + e.params[index]);
    return de;
}

bool curveType(int t) {
    return t == 100 || t == 102 || t == 104 || t == 106 || t == 110 || t == 112 || t == 126 ||
           t == 130;
}
bool surfaceType(int t) {
    return t == 108 || t == 114 || t == 118 || t == 120 || t == 122 || t == 128 || t == 140 ||
           t == 143 || t == 144 || (t >= 190 && t <= 198);
}

/// A pointer that must refer to an entity of the given kind (curve, surface, or one type).
int typed(const File& f, const Entity& e, std::size_t index, bool (*kind)(int), const char* what) {
    const int de = nonNull(f, e, index);
    const Entity& to = *f.at(de);
    if (!kind(to.type))
        failEntity(f, e,
                   parameterName(index) + " = " + std::to_string(de) + " points to " +
                       describe(to) + ", not " + what);
    return de;
}

bool curveOnSurface(int t) {
    return t == 142;
}

/// A 0/1 flag.
int flag(const File& f, const Entity& e, std::size_t index) {
    const int v = integer(f, e, index);
    if (v != 0 && v != 1)
        failEntity(f, e, parameterName(index) + " (a flag) is " + e.params[index] + ", not 0 or 1");
    return v;
}

/// An index into an edge list (504) or vertex list (502): in [1, its count].
void listIndex(const File& f, const Entity& e, std::size_t index, const Entity& list) {
    const int i = integer(f, e, index);
    const int n = list.params.empty() ? 0 : integer(f, list, 0);
    if (i < 1 || i > n)
        failEntity(f, e,
                   parameterName(index) + " = " + e.params[index] + " is not an index into " +
                       describe(list) + " (1 to " + std::to_string(n) + ")");
}

}  // namespace

void check(const File& f, const Entity& e) {
    const int limit = static_cast<int>(f.entities.size()) + 1;
    switch (e.type) {
        case 128:
            checkSurface128(f, e);
            break;
        case 126:
            checkCurve126(f, e);
            break;
        case 110:
            needCount(f, e, 6, "line");
            if (real(f, e, 0) == real(f, e, 3) && real(f, e, 1) == real(f, e, 4) &&
                real(f, e, 2) == real(f, e, 5))
                failEntity(f, e, "a line of zero length (its two points are the same)");
            break;
        case 100:
            needCount(f, e, 7, "circular arc");
            for (std::size_t k = 0; k < 7; ++k) (void)real(f, e, k);
            if (real(f, e, 1) == real(f, e, 3) && real(f, e, 2) == real(f, e, 4))
                failEntity(f, e, "a circular arc of radius 0 (its start is its centre)");
            break;
        case 124:
            needCount(f, e, 12, "transformation matrix");
            for (std::size_t k = 0; k < 12; ++k) (void)real(f, e, k);
            break;
        case 102: {
            needCount(f, e, 1, "composite curve");
            const int n = count(f, e, 0, limit, 1);
            needCount(f, e, 1 + static_cast<std::size_t>(n), "composite curve");
            for (int k = 0; k < n; ++k)
                typed(f, e, 1 + static_cast<std::size_t>(k), curveType, "a curve");
            break;
        }
        case 142: {
            needCount(f, e, 5, "curve on a surface");
            typed(f, e, 1, surfaceType, "a surface");
            const int b = pointer(f, e, 2), c = pointer(f, e, 3);
            if (b == 0 && c == 0)
                failEntity(f, e, "has neither a parameter-space curve nor a model-space curve");
            if (b != 0) typed(f, e, 2, curveType, "a curve");
            if (c != 0) typed(f, e, 3, curveType, "a curve");
            const int pref = integer(f, e, 4);
            if (pref < 0 || pref > 3)
                failEntity(
                    f, e, "parameter 5 (preferred representation) is " + e.params[4] + ", not 0-3");
            break;
        }
        case 144: {
            needCount(f, e, 4, "trimmed surface");
            typed(f, e, 0, surfaceType, "a surface");
            const int n1 = integer(f, e, 1);
            if (n1 != 0 && n1 != 1)
                failEntity(f, e,
                           "parameter 2 (outer boundary flag) is " + e.params[1] + ", not 0 or 1");
            const int n2 = count(f, e, 2, limit);
            needCount(f, e, 4 + static_cast<std::size_t>(n2), "trimmed surface");
            if (n1 == 1)
                typed(f, e, 3, curveOnSurface, "a curve on a surface (142)");
            else
                (void)pointer(f, e, 3);
            for (int k = 0; k < n2; ++k)
                typed(f, e, 4 + static_cast<std::size_t>(k), curveOnSurface,
                      "a curve on a surface (142)");
            break;
        }
        case 143: {
            needCount(f, e, 3, "bounded surface");
            typed(f, e, 1, surfaceType, "a surface");
            const int n = count(f, e, 2, limit, 1);
            needCount(f, e, 3 + static_cast<std::size_t>(n), "bounded surface");
            for (int k = 0; k < n; ++k) nonNull(f, e, 3 + static_cast<std::size_t>(k));
            break;
        }
        case 141: {
            needCount(f, e, 4, "boundary");
            nonNull(f, e, 2);
            const int n = count(f, e, 3, limit, 1);
            std::size_t at = 4;
            for (int k = 0; k < n; ++k) {
                needCount(f, e, at + 3, "boundary");
                nonNull(f, e, at);
                const int m = count(f, e, at + 2, limit);
                needCount(f, e, at + 3 + static_cast<std::size_t>(m), "boundary");
                for (int j = 0; j < m; ++j) nonNull(f, e, at + 3 + static_cast<std::size_t>(j));
                at += 3 + static_cast<std::size_t>(m);
            }
            break;
        }
        case 120:
            needCount(f, e, 4, "surface of revolution");
            typed(
                f, e, 0, [](int t) { return t == 110; }, "a line (the axis)");
            typed(f, e, 1, curveType, "a curve");
            (void)real(f, e, 2);
            (void)real(f, e, 3);
            break;
        case 118:
            needCount(f, e, 4, "ruled surface");
            typed(f, e, 0, curveType, "a curve");
            typed(f, e, 1, curveType, "a curve");
            break;
        case 122:
            needCount(f, e, 4, "tabulated cylinder");
            typed(f, e, 0, curveType, "a curve");
            for (std::size_t k = 1; k < 4; ++k) (void)real(f, e, k);
            break;
        case 140:
            needCount(f, e, 5, "offset surface");
            typed(f, e, 4, surfaceType, "a surface");
            break;
        case 108:
            needCount(f, e, 4, "plane");
            for (std::size_t k = 0; k < 4; ++k) (void)real(f, e, k);
            if (e.params.size() > 4) (void)pointer(f, e, 4);
            break;
        case 186: {
            needCount(f, e, 3, "manifold solid");
            typed(
                f, e, 0, [](int t) { return t == 514; }, "a shell (514)");
            flag(f, e, 1);
            const int n = count(f, e, 2, limit);
            needCount(f, e, 3 + 2 * static_cast<std::size_t>(n), "manifold solid");
            for (int k = 0; k < n; ++k) {
                typed(
                    f, e, 3 + 2 * static_cast<std::size_t>(k), [](int t) { return t == 514; },
                    "a shell (514)");
                flag(f, e, 4 + 2 * static_cast<std::size_t>(k));
            }
            break;
        }
        case 514: {
            needCount(f, e, 1, "shell");
            const int n = count(f, e, 0, limit, 1);
            needCount(f, e, 1 + 2 * static_cast<std::size_t>(n), "shell");
            for (int k = 0; k < n; ++k) {
                typed(
                    f, e, 1 + 2 * static_cast<std::size_t>(k), [](int t) { return t == 510; },
                    "a face (510)");
                flag(f, e, 2 + 2 * static_cast<std::size_t>(k));
            }
            break;
        }
        case 510: {
            needCount(f, e, 3, "face");
            typed(f, e, 0, surfaceType, "a surface");
            const int n = count(f, e, 1, limit, 1);
            flag(f, e, 2);
            needCount(f, e, 3 + static_cast<std::size_t>(n), "face");
            for (int k = 0; k < n; ++k)
                typed(
                    f, e, 3 + static_cast<std::size_t>(k), [](int t) { return t == 508; },
                    "a loop (508)");
            break;
        }
        case 508: {
            needCount(f, e, 1, "loop");
            const int n = count(f, e, 0, limit, 1);
            std::size_t at = 1;
            for (int k = 0; k < n; ++k) {
                needCount(f, e, at + 5, "loop");
                const int type = flag(f, e, at);  // 0: an edge of an edge list, 1: a vertex
                const int list = typed(
                    f, e, at + 1,
                    type == 0 ? +[](int t) { return t == 504; } : +[](int t) { return t == 502; },
                    type == 0 ? "an edge list (504)" : "a vertex list (502)");
                listIndex(f, e, at + 2, *f.at(list));
                flag(f, e, at + 3);
                const int m = count(f, e, at + 4, limit);
                needCount(f, e, at + 5 + 2 * static_cast<std::size_t>(m), "loop");
                for (int j = 0; j < m; ++j) {
                    flag(f, e, at + 5 + 2 * static_cast<std::size_t>(j));
                    typed(f, e, at + 6 + 2 * static_cast<std::size_t>(j), curveType, "a curve");
                }
                at += 5 + 2 * static_cast<std::size_t>(m);
            }
            break;
        }
        case 504: {
            needCount(f, e, 1, "edge list");
            const int n = count(f, e, 0, limit, 1);
            needCount(f, e, 1 + 5 * static_cast<std::size_t>(n), "edge list");
            for (int k = 0; k < n; ++k) {
                const std::size_t at = 1 + 5 * static_cast<std::size_t>(k);
                typed(f, e, at, curveType, "a curve");
                for (std::size_t v : {at + 1, at + 3}) {
                    const int list = typed(
                        f, e, v, [](int t) { return t == 502; }, "a vertex list (502)");
                    listIndex(f, e, v + 1, *f.at(list));
                }
            }
            break;
        }
        case 502: {
            needCount(f, e, 1, "vertex list");
            const int n = count(f, e, 0, 10000000, 1);
            needCount(f, e, 1 + 3 * static_cast<std::size_t>(n), "vertex list");
            for (std::size_t k = 1; k <= 3 * static_cast<std::size_t>(n); ++k) (void)real(f, e, k);
            break;
        }
        default:
            break;
    }
}

std::vector<int> geometryChildren(const File& f, const Entity& e) {
    std::vector<int> out;
    auto add = [&](std::size_t index) {
        if (index < e.params.size()) {
            const int de = integer(f, e, index);
            if (de > 0 && f.at(de)) out.push_back(de);
        }
    };
    auto addList = [&](std::size_t countIndex, std::size_t first, std::size_t stride) {
        if (countIndex >= e.params.size()) return;
        const int n = integer(f, e, countIndex);
        for (int k = 0; k < n; ++k) add(first + stride * static_cast<std::size_t>(k));
    };
    switch (e.type) {
        case 144:
            add(0);
            add(3);
            addList(2, 4, 1);
            break;
        case 142:
            add(1);
            add(2);
            add(3);
            break;
        case 143:
            add(1);
            addList(2, 3, 1);
            break;
        case 141: {
            add(2);
            const int n = integer(f, e, 3);
            std::size_t at = 4;
            for (int k = 0; k < n; ++k) {
                add(at);
                const int m = integer(f, e, at + 2);
                for (int j = 0; j < m; ++j) add(at + 3 + static_cast<std::size_t>(j));
                at += 3 + static_cast<std::size_t>(m);
            }
            break;
        }
        case 102:
            addList(0, 1, 1);
            break;
        case 120:
        case 118:
            add(0);
            add(1);
            break;
        case 122:
            add(0);
            break;
        case 140:
            add(4);
            break;
        case 108:
            add(4);
            break;
        case 186:
            add(0);
            addList(2, 3, 2);
            break;
        case 514:
            addList(0, 1, 2);
            break;
        case 510:
            add(0);
            addList(1, 3, 1);
            break;
        case 508: {
            const int n = integer(f, e, 0);
            std::size_t at = 1;
            for (int k = 0; k < n; ++k) {
                add(at + 1);
                const int m = integer(f, e, at + 4);
                for (int j = 0; j < m; ++j) add(at + 6 + 2 * static_cast<std::size_t>(j));
                at += 5 + 2 * static_cast<std::size_t>(m);
            }
            break;
        }
        case 504: {
            const int n = integer(f, e, 0);
            for (int k = 0; k < n; ++k) {
                add(1 + 5 * static_cast<std::size_t>(k));
                add(2 + 5 * static_cast<std::size_t>(k));
                add(4 + 5 * static_cast<std::size_t>(k));
            }
            break;
        }
        case 190:
            add(0);
            add(1);
            if (e.form == 1) add(2);
            break;
        case 192:
            add(0);
            add(1);
            if (e.form == 1) add(3);
            break;
        case 194:
            add(0);
            add(1);
            if (e.form == 1) add(4);
            break;
        case 196:
            add(0);
            if (e.form == 1) {
                add(2);
                add(3);
            }
            break;
        case 198:
            add(0);
            add(1);
            if (e.form == 1) add(4);
            break;
        case 408:
            add(0);
            break;
        case 308:
            addList(2, 3, 1);
            break;
        default:
            break;
    }
    return out;
}

void checkCycles(const File& f) {
    // Iterative depth-first search over the geometry pointers; a pointer back to an entity on the
    // current path is a cycle (OpenCASCADE would recurse without end).
    std::vector<char> state(f.entities.size(), 0);  // 0 new, 1 on the path, 2 done
    for (const Entity& root : f.entities) {
        if (state[static_cast<std::size_t>(root.de / 2)]) continue;
        std::vector<std::pair<const Entity*, std::vector<int>>> stack;
        stack.push_back({&root, geometryChildren(f, root)});
        state[static_cast<std::size_t>(root.de / 2)] = 1;
        while (!stack.empty()) {
            auto& [e, children] = stack.back();
            if (children.empty()) {
                state[static_cast<std::size_t>(e->de / 2)] = 2;
                stack.pop_back();
                continue;
            }
            const int c = children.back();
            children.pop_back();
            const Entity& child = *f.at(c);
            char& s = state[static_cast<std::size_t>(c / 2)];
            if (s == 1)
                failEntity(f, *e,
                           "refers to " + describe(child) +
                               ", which refers back to it: the entities form a cycle");
            if (s == 0) {
                s = 1;
                stack.push_back({&child, geometryChildren(f, child)});
            }
        }
    }
}

std::string typeName(int type) {
    switch (type) {
        case 100:
            return "circular arc";
        case 102:
            return "composite curve";
        case 104:
            return "conic arc";
        case 106:
            return "copious data";
        case 108:
            return "plane";
        case 110:
            return "line";
        case 112:
            return "parametric spline curve";
        case 114:
            return "parametric spline surface";
        case 116:
            return "point";
        case 118:
            return "ruled surface";
        case 120:
            return "surface of revolution";
        case 122:
            return "tabulated cylinder";
        case 123:
            return "direction";
        case 124:
            return "transformation matrix";
        case 125:
            return "flash";
        case 126:
            return "rational B-spline curve";
        case 128:
            return "rational B-spline surface";
        case 130:
            return "offset curve";
        case 140:
            return "offset surface";
        case 141:
            return "boundary";
        case 142:
            return "curve on a parametric surface";
        case 143:
            return "bounded surface";
        case 144:
            return "trimmed surface";
        case 186:
            return "manifold solid B-rep";
        case 190:
            return "plane surface";
        case 192:
            return "right circular cylindrical surface";
        case 194:
            return "right circular conical surface";
        case 196:
            return "spherical surface";
        case 198:
            return "toroidal surface";
        case 202:
            return "angular dimension";
        case 206:
            return "diameter dimension";
        case 210:
            return "general label";
        case 212:
            return "general note";
        case 214:
            return "leader (arrow)";
        case 216:
            return "linear dimension";
        case 222:
            return "radius dimension";
        case 228:
            return "general symbol";
        case 304:
            return "line font definition";
        case 308:
            return "subfigure definition";
        case 314:
            return "colour definition";
        case 402:
            return "associativity instance";
        case 404:
            return "drawing";
        case 406:
            return "property";
        case 408:
            return "singular subfigure instance";
        case 410:
            return "view";
        case 502:
            return "vertex list";
        case 504:
            return "edge list";
        case 508:
            return "loop";
        case 510:
            return "face";
        case 514:
            return "shell";
        default:
            return "entity type " + std::to_string(type);
    }
}

}  // namespace aero::cad::iges
