// ISO 10303-21 exchange-structure check (see StepText.h). A recursive-descent reading of the
// tokens, keeping nothing but the entity ids and the references.
#include "cad/StepText.h"

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "common/Error.h"

namespace aero::cad::step {

namespace {

enum class Tok { End, Keyword, EntityName, String, Number, Enumeration, Binary, Open, Close, Comma, Semicolon, Equals, Dollar, Star };

const char* tokName(Tok t) {
    switch (t) {
        case Tok::End: return "the end of the file";
        case Tok::Keyword: return "a keyword";
        case Tok::EntityName: return "an entity name (#n)";
        case Tok::String: return "a string";
        case Tok::Number: return "a number";
        case Tok::Enumeration: return "an enumeration (.X.)";
        case Tok::Binary: return "a binary value";
        case Tok::Open: return "'('";
        case Tok::Close: return "')'";
        case Tok::Comma: return "','";
        case Tok::Semicolon: return "';'";
        case Tok::Equals: return "'='";
        case Tok::Dollar: return "'$'";
        case Tok::Star: return "'*'";
    }
    return "a token";
}

constexpr int kMaxDepth = 200;  // nested lists and typed parameters (real files: < 10)

class Checker {
public:
    Checker(std::string_view text, const std::string& path) : s_(text), path_(path) { next(); }

    void run() {
        keyword("ISO-10303-21", "the file must start with ISO-10303-21;");
        expect(Tok::Semicolon, "after ISO-10303-21");
        header();
        int sections = 0;
        while (tok_ == Tok::Keyword && word_ == "DATA") {
            data();
            ++sections;
        }
        if (sections == 0) fail("expected a DATA section after the header, found " + found());
        if (tok_ == Tok::End) fail("the file ends without END-ISO-10303-21; (truncated?)");
        keyword("END-ISO-10303-21", "expected DATA or END-ISO-10303-21");
        expect(Tok::Semicolon, "after END-ISO-10303-21");
        // Anything after the terminator is ignored by readers.
        std::size_t dangling = 0;
        const Reference* first = nullptr;
        for (const Reference& r : refs_) {
            if (defined_.count(r.id)) continue;
            if (!first) first = &r;
            ++dangling;
        }
        if (first) {
            line_ = first->line;
            entity_ = first->from;
            fail("refers to #" + std::to_string(first->id) + ", which the file does not define" +
                 (dangling > 1 ? " (" + std::to_string(dangling) + " such references in the file)" : ""));
        }
        checkCycles();
    }

private:
    struct Reference {
        std::uint64_t id;
        std::uint64_t from;
        long line;
    };
    struct Definition {
        std::uint64_t id;
        long line;
    };

    // The data entities' references form a hierarchy (a face refers to its loops, a loop to its
    // edges, an edge to its vertices): a cycle (an oriented edge whose edge element is itself,
    // found by fuzz_step) makes OpenCASCADE's reader recurse along it until the stack overflows.
    // A depth-first search without recursion (files have millions of entities), from each entity
    // in the order the file defines them, so the cycle named is the same every time.
    void checkCycles() {
        const std::size_t n = definitions_.size();
        std::unordered_map<std::uint64_t, std::uint32_t> index;
        index.reserve(n);
        for (std::size_t v = 0; v < n; ++v) index.emplace(definitions_[v].id, static_cast<std::uint32_t>(v));
        std::vector<std::uint32_t> start(n + 1, 0), target;
        for (const Reference& r : refs_) {
            if (r.from) ++start[index.at(r.from) + 1];
        }
        for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
        target.resize(start[n]);
        {
            std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
            for (const Reference& r : refs_) {
                if (r.from) target[next[index.at(r.from)]++] = index.at(r.id);
            }
        }
        std::vector<char> state(n, 0);  // 0 not seen, 1 on the current path, 2 done
        std::vector<std::pair<std::uint32_t, std::uint32_t>> path;  // entity, its next reference
        for (std::uint32_t root = 0; root < n; ++root) {
            if (state[root]) continue;
            state[root] = 1;
            path.push_back({root, start[root]});
            while (!path.empty()) {
                auto& [v, e] = path.back();
                if (e == start[v + 1]) {
                    state[v] = 2;
                    path.pop_back();
                    continue;
                }
                const std::uint32_t w = target[e++];
                if (state[w] == 2) continue;
                if (state[w] == 0) {
                    state[w] = 1;
                    path.push_back({w, start[w]});
                    continue;
                }
                // w is on the path: the cycle runs from it to v and back.
                std::size_t from = path.size() - 1;
                while (path[from].first != w) --from;
                std::string chain;
                const std::size_t length = path.size() - from;
                for (std::size_t k = from; k < path.size(); ++k) {
                    if (length > 8 && k == from + 4) {
                        chain += " -> ... (" + std::to_string(length - 6) + " more)";
                        k = path.size() - 3;
                        continue;
                    }
                    chain += (chain.empty() ? "#" : " -> #") + std::to_string(definitions_[path[k].first].id);
                }
                chain += " -> #" + std::to_string(definitions_[w].id);
                line_ = definitions_[w].line;
                entity_ = definitions_[w].id;
                fail(length == 1 ? "refers to itself (" + chain + "); entity references must not form a cycle"
                                 : "is part of a cycle of references (" + chain +
                                       "); entity references must not form a cycle");
            }
        }
    }

    [[noreturn]] void fail(const std::string& why) const {
        std::string where = "STEP file '" + path_ + "', line " + std::to_string(line_);
        if (entity_) where += ", entity #" + std::to_string(entity_);
        throw InputError(where + ": " + why);
    }

    std::string found() const {
        if (tok_ == Tok::Keyword) return "'" + word_ + "'";
        return tokName(tok_);
    }

    void skipBlanksAndComments() {
        while (pos_ < s_.size()) {
            const char c = s_[pos_];
            if (c == '\n') {
                ++lineAt_;
                ++pos_;
            } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
                ++pos_;
            } else if (c == '/' && pos_ + 1 < s_.size() && s_[pos_ + 1] == '*') {
                const long start = lineAt_;
                pos_ += 2;
                for (;;) {
                    if (pos_ + 1 >= s_.size()) {
                        line_ = start;
                        fail("a comment (/*) is not closed");
                    }
                    if (s_[pos_] == '*' && s_[pos_ + 1] == '/') {
                        pos_ += 2;
                        break;
                    }
                    if (s_[pos_] == '\n') ++lineAt_;
                    ++pos_;
                }
            } else {
                return;
            }
        }
    }

    static bool keywordChar(char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
    }

    // Reads the next token into tok_ (word_ holds a keyword's text, id_ an entity name's number).
    void next() {
        skipBlanksAndComments();
        line_ = lineAt_;
        if (pos_ >= s_.size()) {
            tok_ = Tok::End;
            return;
        }
        const char c = s_[pos_];
        switch (c) {
            case '(': tok_ = Tok::Open; ++pos_; return;
            case ')': tok_ = Tok::Close; ++pos_; return;
            case ',': tok_ = Tok::Comma; ++pos_; return;
            case ';': tok_ = Tok::Semicolon; ++pos_; return;
            case '=': tok_ = Tok::Equals; ++pos_; return;
            case '$': tok_ = Tok::Dollar; ++pos_; return;
            case '*': tok_ = Tok::Star; ++pos_; return;
            default: break;
        }
        if (c == '\'') {
            // A string: '' is a quote inside it; everything else (including ; and parentheses)
            // is text.
            const long start = lineAt_;
            ++pos_;
            for (;;) {
                if (pos_ >= s_.size()) {
                    line_ = start;
                    fail("a string is not closed (no matching ')");
                }
                const char d = s_[pos_++];
                if (d == '\n') ++lineAt_;
                if (d == '\'') {
                    if (pos_ < s_.size() && s_[pos_] == '\'') {
                        ++pos_;
                        continue;
                    }
                    break;
                }
            }
            tok_ = Tok::String;
            return;
        }
        if (c == '"') {
            ++pos_;
            while (pos_ < s_.size() && std::isxdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
            if (pos_ >= s_.size() || s_[pos_] != '"') fail("a binary value (\"...\") is not closed or has a non-hex digit");
            ++pos_;
            tok_ = Tok::Binary;
            return;
        }
        if (c == '#') {
            ++pos_;
            const std::size_t start = pos_;
            std::uint64_t id = 0;
            while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) {
                if (pos_ - start >= 18) fail("an entity name has more than 18 digits");
                id = 10 * id + static_cast<std::uint64_t>(s_[pos_] - '0');
                ++pos_;
            }
            if (pos_ == start) fail("'#' is not followed by an entity number");
            tok_ = Tok::EntityName;
            id_ = id;
            return;
        }
        if (c == '.') {
            // An enumeration (.T., .UNSPECIFIED.) -- or a real starting with its point (.5).
            if (pos_ + 1 < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_ + 1]))) {
                number();
                return;
            }
            ++pos_;
            const std::size_t start = pos_;
            while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
            if (pos_ == start || pos_ >= s_.size() || s_[pos_] != '.') fail("an enumeration value (.X.) is not closed");
            ++pos_;
            tok_ = Tok::Enumeration;
            return;
        }
        if (c == '+' || c == '-' || std::isdigit(static_cast<unsigned char>(c))) {
            number();
            return;
        }
        if (std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == '!') {
            const std::size_t start = pos_++;
            while (pos_ < s_.size() && keywordChar(s_[pos_])) ++pos_;
            word_.assign(s_.substr(start, pos_ - start));
            tok_ = Tok::Keyword;
            return;
        }
        const unsigned char u = static_cast<unsigned char>(c);
        char code[8];
        std::snprintf(code, sizeof code, "0x%02x", u);
        fail(std::isprint(u) ? std::string("unexpected character '") + c + "'"
                             : std::string("unexpected byte ") + code + " outside a string");
    }

    void number() {
        const std::size_t start = pos_;
        if (s_[pos_] == '+' || s_[pos_] == '-') ++pos_;
        std::size_t digits = 0;
        while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_, ++digits;
        if (pos_ < s_.size() && s_[pos_] == '.') {
            ++pos_;
            while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_, ++digits;
        }
        if (digits == 0) fail("'" + std::string(s_.substr(start, pos_ - start + 1)) + "' is not a number");
        if (pos_ < s_.size() && (s_[pos_] == 'E' || s_[pos_] == 'e')) {
            ++pos_;
            if (pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-')) ++pos_;
            const std::size_t e = pos_;
            while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
            if (pos_ == e) fail("a number's exponent has no digits");
        }
        tok_ = Tok::Number;
    }

    void expect(Tok t, const std::string& where) {
        if (tok_ != t) fail(std::string("expected ") + tokName(t) + " " + where + ", found " + found());
        next();
    }

    void keyword(const char* k, const std::string& why) {
        if (tok_ != Tok::Keyword || word_ != k) fail(why + " (found " + found() + ")");
        next();
    }

    // A parameter list after its '(' up to and including ')'.
    void parameters(int depth) {
        if (depth > kMaxDepth) fail("parameters nested deeper than " + std::to_string(kMaxDepth) + " lists");
        if (tok_ == Tok::Close) {
            next();
            return;
        }
        for (;;) {
            parameter(depth);
            if (tok_ == Tok::Comma) {
                next();
                continue;
            }
            if (tok_ == Tok::Close) {
                next();
                return;
            }
            fail("expected ',' or ')' in a parameter list, found " + found());
        }
    }

    void parameter(int depth) {
        switch (tok_) {
            case Tok::String:
            case Tok::Number:
            case Tok::Enumeration:
            case Tok::Binary:
            case Tok::Dollar:
            case Tok::Star:
                next();
                return;
            case Tok::EntityName:
                refs_.push_back({id_, entity_, line_});
                next();
                return;
            case Tok::Open:
                next();
                parameters(depth + 1);
                return;
            case Tok::Keyword:  // a typed parameter, e.g. LENGTH_MEASURE(1.0)
                next();
                expect(Tok::Open, "after a typed parameter's keyword");
                parameters(depth + 1);
                return;
            default:
                fail("expected a parameter, found " + found() +
                     (tok_ == Tok::Comma || tok_ == Tok::Close ? " (an empty list element)" : ""));
        }
    }

    // KEYWORD(params), the keyword current (the caller reads what follows).
    void record(const std::string& what) {
        if (tok_ != Tok::Keyword) fail("expected " + what + ", found " + found());
        next();
        expect(Tok::Open, "after the keyword");
        parameters(0);
    }

    // The header's entities (FILE_DESCRIPTION, FILE_NAME, FILE_SCHEMA by the standard) are
    // checked for syntax only: OpenCASCADE reads files whose header lacks some or has them out of
    // order, and so do we.
    void header() {
        keyword("HEADER", "expected HEADER; after ISO-10303-21;");
        expect(Tok::Semicolon, "after HEADER");
        while (tok_ == Tok::Keyword && word_ != "ENDSEC") {
            record("a header entity");
            expect(Tok::Semicolon, "after a header entity");
        }
        if (tok_ == Tok::End) fail("the file ends inside the header (truncated?)");
        keyword("ENDSEC", "expected a header entity or ENDSEC");
        expect(Tok::Semicolon, "after ENDSEC");
    }

    void data() {
        next();  // DATA
        if (tok_ == Tok::Open) {  // DATA('name', (schema)) of the third edition
            next();
            parameters(0);
        }
        expect(Tok::Semicolon, "after DATA");
        while (tok_ == Tok::EntityName) {
            entity_ = id_;
            if (!defined_.insert(id_).second) fail("is defined twice");
            definitions_.push_back({id_, line_});
            next();
            expect(Tok::Equals, "after the entity name");
            if (tok_ == Tok::Open) {
                // A complex instance: (A(...) B(...) ...)
                next();
                int parts = 0;
                while (tok_ == Tok::Keyword) {
                    record("a partial entity");
                    ++parts;
                }
                if (parts == 0) fail("a complex entity instance has no partial entities");
                expect(Tok::Close, "after a complex entity instance's parts");
            } else {
                record("an entity type keyword");
            }
            if (tok_ != Tok::Semicolon) fail("expected ';' at the end of the entity instance, found " + found());
            entity_ = 0;  // what follows (a comment, the next statement) is not this entity's
            next();
        }
        if (tok_ == Tok::End) fail("the file ends inside the DATA section (truncated?)");
        keyword("ENDSEC", "expected an entity instance (#n = ...) or ENDSEC in the DATA section");
        expect(Tok::Semicolon, "after ENDSEC");
    }

    std::string_view s_;
    const std::string& path_;
    std::size_t pos_ = 0;
    long lineAt_ = 1;      // line of pos_
    long line_ = 1;        // line of the current token
    Tok tok_ = Tok::End;
    std::string word_;
    std::uint64_t id_ = 0;
    std::uint64_t entity_ = 0;  // the data entity being read (0: none)
    std::unordered_set<std::uint64_t> defined_;
    std::vector<Reference> refs_;
    std::vector<Definition> definitions_;  // in the order the file defines them
};

}  // namespace

void checkExchangeStructure(std::string_view text, const std::string& path) {
    Checker(text, path).run();
}

}  // namespace aero::cad::step
