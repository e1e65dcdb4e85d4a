/* The JSON reader (host/util/json.c) on valid and malformed text. */
#include "json.h"
#include "testutil.h"
#include <string.h>

static spm_json *parse(const char *s, char *why)
{
    return spm_json_parse(s, strlen(s), why, 200);
}

static void valid(void)
{
    char why[200];
    spm_json *v = parse(" {\"a\": [1, -2.5e3, true, null, {}], \"s\": \"x\\\"\\u00e9\\ud83d\\ude00\\n\","
                        " \"buffers\": [{\"uri\": \"a b.bin\"}]} ", why);
    CHECK(v != NULL, "parsed: %s", why);
    if (!v)
        return;
    const spm_json *a = spm_json_get(v, "a");
    CHECK(a && a->type == SPM_JSON_ARRAY && a->n == 5, "array of 5");
    CHECK(a && a->items[1].number == -2500.0, "-2.5e3");
    CHECK(a && a->items[2].type == SPM_JSON_BOOL && a->items[2].number == 1, "true");
    CHECK(a && a->items[3].type == SPM_JSON_NULL && a->items[4].type == SPM_JSON_OBJECT, "null, {}");
    const char *s = spm_json_string(v, "s");
    CHECK(s && !strcmp(s, "x\"\xc3\xa9\xf0\x9f\x98\x80\n"), "escapes to UTF-8: %s", s ? s : "(none)");
    const spm_json *b = spm_json_get(v, "buffers");
    CHECK(b && b->n == 1 && !strcmp(spm_json_string(&b->items[0], "uri"), "a b.bin"), "uri");
    CHECK(spm_json_get(v, "missing") == NULL && spm_json_string(v, "a") == NULL, "absent, not a string");
    spm_json_free(v);
}

static void invalid(void)
{
    static const char *const bad[][2] = {
        {"{\"a\": 1", "',' or '}'"},           {"[1, 2", "',' or ']'"},
        {"\"abc", "closing '\"'"},             {"{\"a\" 1}", "':'"},
        {"[1] x", "the end of the text"},      {"\"\\ud800\"", "low half"},
        {"\"\\q\"", "an escape"},              {"\"\\u0000\"", "\\u0000"},
        {"[tru]", "a value"},                  {"", "a value, not the end"},
        {"\"a\tb\"", "control character"},     {"{1: 2}", "member's name"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char why[200];
        spm_json *v = parse(bad[i][0], why);
        CHECK(v == NULL && strstr(why, bad[i][1]) && strstr(why, "line 1, column"),
              "'%s' refused saying '%s': %s", bad[i][0], bad[i][1], v ? "(accepted)" : why);
        spm_json_free(v);
    }
    char deep[400], why[200];
    memset(deep, '[', 200);
    memset(deep + 200, ']', 200);
    spm_json *v = spm_json_parse(deep, 400, why, sizeof why);
    CHECK(v == NULL && strstr(why, "128 nested"), "200 nested arrays refused: %s", why);
    spm_json_free(v);
    v = parse("{\"a\":\n  [1,\n  2 3]}", why);
    CHECK(v == NULL && strstr(why, "line 3, column 5"), "position: %s", why);
    spm_json_free(v);
}

int main(void)
{
    valid();
    invalid();
    TEST_END();
}
