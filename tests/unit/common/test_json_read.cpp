// json_read (lib/src/common/json_read.h), the one JSON reading helper of the
// parsers: syntax errors with line and column, allowed / required keys, the
// number policy (finite; "inf" only where allowed; never NaN), key paths,
// codes and subjects.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/json_read.h"

using namespace gdof;
using namespace gdof::json_read;

namespace {

// Runs read on the parsed text under source "doc.json"; the error it gives.
template <class F>
Status error_of(const std::string& text, F&& read, Comments comments = Comments::Rejected) {
    auto r = read_document(text, "doc.json", read, comments);
    EXPECT_FALSE(r) << "read but should not: " << text;
    return r.status();
}

double number_at(const Value& root, const std::string& key, Infinity inf = Infinity::Rejected) {
    return root.object().get(key).number(inf);
}

}  // namespace

TEST(json_read, SyntaxErrorsGiveLineAndColumnOfTheOffendingToken) {
    // The second comma is at line 3, column 14.
    Status st = error_of("{\n  \"a\": 1,\n  \"b\": [1, 2,,]\n}", [](const Value&) { return 0; });
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_EQ(st.message().rfind("doc.json: malformed JSON at line 3, column 14: syntax error", 0), 0u) << st.message();
    // Empty text: line 1, column 1.
    st = error_of("", [](const Value&) { return 0; });
    EXPECT_NE(st.message().find("malformed JSON at line 1, column 1"), std::string::npos) << st.message();
    // Without a source, the message starts with the problem.
    auto r = parse("[1, 2");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.message().rfind("malformed JSON at line 1, column 5: ", 0), 0u) << r.message();
}

TEST(json_read, CommentsOnlyWhereAllowed) {
    const std::string text = "{\"a\": 1 // one\n}";
    EXPECT_FALSE(parse(text));
    auto r = parse(text, Comments::Allowed);
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r.value()["a"], 1);
}

TEST(json_read, ParseBuildsTheSameDocumentAsTheLibrary) {
    const std::string text = R"({"b": {"x": [1, {"y": 2}], "x": 3}, "a": [[], {}, null, true, 2.5, -3, 18446744073709551615, "s"]})";
    auto r = parse(text);
    ASSERT_TRUE(r) << r.message();
    EXPECT_EQ(r.value(), json::parse(text));
    EXPECT_EQ(r.value()["b"]["x"], 3);  // a repeated key keeps the last value
}

TEST(json_read, NumberOverflowIsASyntaxErrorAtTheNumber) {
    for (const char* lit : {"1e999", "-1e999"}) {
        const std::string text = std::string("{\"a\": 1,\n \"b\": ") + lit + "}";
        Status st = error_of(text, [](const Value&) { return 0; });
        EXPECT_NE(st.message().find("line 2, column 7"), std::string::npos) << st.message();
        EXPECT_NE(st.message().find(std::string("number overflow parsing '") + lit + "'"), std::string::npos) << st.message();
        EXPECT_NE(st.message().find("numbers must be finite"), std::string::npos) << st.message();
    }
}

TEST(json_read, NumbersAreFiniteAndInfOnlyWhereAllowed) {
    auto read_a = [](const Value& root) { return number_at(root, "a"); };
    auto read_a_inf = [](const Value& root) { return number_at(root, "a", Infinity::Allowed); };
    // "inf", "nan" and "1e999" as strings are wrong types unless "inf" is allowed.
    for (const char* s : {"\"inf\"", "\"nan\"", "\"1e999\"", "\"infinity\"", "\"-inf\""}) {
        Status st = error_of(std::string("{\"a\": ") + s + "}", read_a);
        EXPECT_EQ(st.message(), std::string("doc.json: a: must be a number, got string ") + s);
        EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
        EXPECT_EQ(st.subject(), "a");
    }
    auto inf = read_document(R"({"a": "inf"})", "doc.json", read_a_inf);
    ASSERT_TRUE(inf) << inf.message();
    EXPECT_EQ(inf.value(), std::numeric_limits<double>::infinity());
    // One spelling: "infinity", "-inf", "nan" stay errors where "inf" is allowed.
    for (const char* s : {"\"infinity\"", "\"-inf\"", "\"nan\"", "\"Inf\""}) {
        Status st = error_of(std::string("{\"a\": ") + s + "}", read_a_inf);
        EXPECT_EQ(st.message(), std::string("doc.json: a: must be a number or \"inf\", got string ") + s);
    }
    // A document built in memory can hold non-finite numbers: rejected, NaN always.
    json j = {{"a", std::numeric_limits<double>::quiet_NaN()}, {"b", std::numeric_limits<double>::infinity()}};
    const Object o = Value(j, "").object();
    auto st = catch_errors("mem", [&] { return o.get("a").number(Infinity::Allowed); });
    ASSERT_FALSE(st);
    EXPECT_EQ(st.message(), "mem: a: must be finite or \"inf\", got nan");
    st = catch_errors("mem", [&] { return o.get("b").number(); });
    ASSERT_FALSE(st);
    EXPECT_EQ(st.message(), "mem: b: must be finite, got inf");
    // Finite literals read exactly.
    auto ok = read_document(R"({"a": -2.5e3})", "doc.json", read_a);
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok.value(), -2500.0);
}

TEST(json_read, RangesAndTypesNameTheValue) {
    auto check = [](const std::string& text, auto read, const std::string& expected) {
        Status st = error_of(text, read);
        EXPECT_EQ(st.message(), expected);
    };
    check(R"({"a": 0})", [](const Value& r) { return r.object().get("a").positive(); }, "doc.json: a: must be > 0, got 0");
    check(R"({"a": -1})", [](const Value& r) { return r.object().get("a").non_negative(); }, "doc.json: a: must be >= 0, got -1");
    check(R"({"a": 0.5})", [](const Value& r) { return r.object().get("a").integer(); }, "doc.json: a: must be an integer, got number");
    check(R"({"a": 1})", [](const Value& r) { return r.object().get("a").boolean(); }, "doc.json: a: must be true or false, got number");
    check(R"({"a": 1})", [](const Value& r) { return r.object().get("a").string(); }, "doc.json: a: must be a string, got number");
    check(R"({"a": "cubic"})", [](const Value& r) { return r.object().get("a").choice({"linear", "smooth"}); },
          "doc.json: a: must be one of linear, smooth, got \"cubic\"");
    check(R"({"a": [1, 2]})", [](const Value& r) { return r.object().get("a").vec3(); },
          "doc.json: a: must be an array of 3 numbers, got array");
    check(R"({"a": [1, "x", 2]})", [](const Value& r) { return r.object().get("a").vec3(); },
          "doc.json: a[1]: must be a number, got string \"x\"");
    check(R"({"a": []})", [](const Value& r) { return r.object().get("a").non_empty_array("depths").size(); },
          "doc.json: a: must be a non-empty array of depths, got array");
    check(R"([1])", [](const Value& r) { return r.object().has("a"); }, "doc.json: top level: must be an object, got array");
}

TEST(json_read, UnknownAndMissingKeys) {
    auto read = [](const Value& root) {
        const Object o = root.object({"near", "far", "comment"}, {"near", "far"});
        return o.get("near").number() + o.get("far").number();
    };
    Status st = error_of(R"({"near": 1, "far": 2, "farr": 3})", read);
    EXPECT_EQ(st.message(), "doc.json: farr: unknown key (allowed: near, far, comment)");
    EXPECT_EQ(st.code(), StatusCode::InvalidArgument);
    EXPECT_EQ(st.subject(), "farr");
    // Unknown keys are reported before missing ones; required keys in order.
    st = error_of(R"({"nearr": 1})", read);
    EXPECT_NE(st.message().find("nearr: unknown key"), std::string::npos) << st.message();
    st = error_of(R"({"far": 1})", read);
    EXPECT_EQ(st.message(), "doc.json: near: missing required key");
    EXPECT_EQ(st.code(), StatusCode::NotFound);
    EXPECT_EQ(st.subject(), "near");
    // A key required where it is read, with the reason.
    st = error_of(R"({})", [](const Value& root) { return root.object().get("slope", "a single depth needs it").number(); });
    EXPECT_EQ(st.message(), "doc.json: slope: missing required key (a single depth needs it)");
    auto ok = read_document(R"({"near": 1, "far": 2, "comment": "x"})", "doc.json", read);
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok.value(), 3.0);
}

TEST(json_read, NestedPathsAndSubjects) {
    auto read = [](const Value& root) {
        const Object o = root.object({"references"});
        double sum = 0;
        for (const Value& r : o.get("references").array()) {
            const Object ro = r.object({"file", "f_number"}, {"file"});
            sum += ro.get("f_number").positive();
        }
        return sum;
    };
    Status st = error_of(R"({"references": [{"file": "a", "f_number": 2}, {"file": "b", "f_number": 4},
                                            {"file": "c", "f_number": -2}]})",
                         read);
    EXPECT_EQ(st.message(), "doc.json: references[2].f_number: must be > 0, got -2");
    EXPECT_EQ(st.subject(), "f_number");
    st = error_of(R"({"references": [{"file": "a", "fnumber": 2}]})", read);
    EXPECT_EQ(st.message(), "doc.json: references[0].fnumber: unknown key (allowed: file, f_number)");
    EXPECT_EQ(st.subject(), "fnumber");
    st = error_of(R"({"references": [{"f_number": 2}]})", read);
    EXPECT_EQ(st.message(), "doc.json: references[0].file: missing required key");
    st = error_of(R"({"references": [3]})", read);
    EXPECT_EQ(st.message(), "doc.json: references[0]: must be an object, got number");
    EXPECT_EQ(st.subject(), "references");
}

TEST(json_read, PathHelpers) {
    EXPECT_EQ(key_path("", "coc_px"), "coc_px");
    EXPECT_EQ(key_path("references[2]", "f_number"), "references[2].f_number");
    EXPECT_EQ(index_path("depths", 3), "depths[3]");
    EXPECT_EQ(subject_of("references[2].f_number"), "f_number");
    EXPECT_EQ(subject_of("far.grid[1][0]"), "grid");
    EXPECT_EQ(subject_of("coc_px"), "coc_px");
    EXPECT_EQ(subject_of(""), "");
    EXPECT_EQ(format_number(0.1), "0.1");
    EXPECT_EQ(format_number(std::numeric_limits<double>::infinity()), "inf");
    EXPECT_EQ(join({"a", "b", "c"}), "a, b, c");
    EXPECT_EQ(type_name(json("x")), "string \"x\"");
}

TEST(json_read, LibraryErrorsKeepTheirCode) {
    auto st = catch_errors("src", [] {
        fail("image", Status::error("'a.exr' not found", StatusCode::NotFound));
        return 0;
    });
    ASSERT_FALSE(st);
    EXPECT_EQ(st.message(), "src: image: 'a.exr' not found");
    EXPECT_EQ(st.status().code(), StatusCode::NotFound);
    EXPECT_EQ(st.status().subject(), "image");
    // Without a path, the error's own subject is kept.
    st = catch_errors("", [] {
        fail("", Status::error("bad lens", StatusCode::InvalidArgument, "f_number"));
        return 0;
    });
    ASSERT_FALSE(st);
    EXPECT_EQ(st.message(), "bad lens");
    EXPECT_EQ(st.status().subject(), "f_number");
}
