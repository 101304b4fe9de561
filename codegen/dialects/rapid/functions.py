"""RAPID's math and string functions: Abs, Round, Trunc, Pow, ACos..., StrLen, StrPart, StrFind, StrMap, ValToStr..."""

from __future__ import annotations

import math

from codegen.dialects.core.values import Record, RunError, f32, format_fixed
from codegen.dialects.rapid.types import STRING_MAX, num, rec, text, vec

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6/7),
# chapter 2 "Functions", as recalled (the manual's text was not readable during this work); uncertain points:
# - trigonometry in degrees; ACos/ASin of a value outside -1..1 is an error; Sqrt/Pow of a negative base with a
#   non-integer exponent an error; Round / Trunc [\Dec:=n]: n decimals (0 by default), Round half away from zero;
# - strings are indexed from 1; StrPart(Str, ChPos, Len) fails outside the string; StrFind / StrMatch return the
#   position found, or StrLen + 1; StrMemb(Str, ChPos, Set) TRUE when that character is in Set; StrMap(Str,
#   FromMap, ToMap) maps each character of FromMap to the one at the same place in ToMap; StrOrder(Str1, Str2,
#   Order) TRUE when Str1 comes before Str2 in the order the string Order gives its characters (others after it);
# - predefined strings STR_DIGIT, STR_UPPER, STR_LOWER (letters of ISO 8859-1), STR_WHITE (the blank) and stEmpty;
# - NumToStr(Val, Dec [\Exp]); ValToStr(Val): a num with up to 6 significant digits, bool TRUE / FALSE, a
#   record as an aggregate without blanks;
# - BitAnd, BitOr, BitXOr, BitNeg, BitLSh, BitRSh, BitCheck on bytes (0..255).
STRINGS = {
    "STR_DIGIT": "0123456789",
    "STR_UPPER": "ABCDEFGHIJKLMNOPQRSTUVWXYZÀÁÂÃÄÅÆÇÈÉÊËÌÍÎÏÐÑÒÓÔÕÖØÙÚÛÜÝÞ",
    "STR_LOWER": "abcdefghijklmnopqrstuvwxyzàáâãäåæçèéêëìíîïðñòóôõöøùúûüýþ",
    "STR_WHITE": " ",
    "STEMPTY": "",
}


def num_text(value) -> str:
    """A num as TPWrite \\Num and ValToStr write it: integers without decimals, else up to 6 significant digits."""
    v = float(value)
    if v == int(v) and abs(v) < 1e9:
        return str(int(v))
    return f"{v:.6g}"


def value_text(value) -> str:
    """A value as ValToStr writes it."""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, str):
        return value
    if isinstance(value, Record | list):
        items = value.values() if isinstance(value, Record) else value
        return "[" + ",".join(_quoted(v) for v in items) + "]"
    return num_text(value)


def _quoted(value) -> str:
    return f'"{value}"' if isinstance(value, str) else value_text(value)


def _string(s: str, where: str) -> str:
    if len(s) > STRING_MAX:
        raise RunError(f"{where}: string of {len(s)} characters: a string holds at most {STRING_MAX}")
    return s


def _position(value, where: str, length: int, what: str) -> int:
    p = num(value, where)
    if p != int(p) or not 1 <= p <= length + 1:
        raise RunError(f"{where}: {what} {p:g} is outside the string (1..{length + 1})")
    return int(p)


def _decimals(kwargs, where: str) -> int:
    if "DEC" not in kwargs:
        return 0
    d = num(kwargs["DEC"], where)
    if d != int(d) or not 0 <= d <= 6:
        raise RunError(f"{where}: \\Dec {d:g}: 0 to 6 decimals")
    return int(d)


def _round(fr, a, k, w):
    d, v = _decimals(k, w), num(a[0], w)
    return f32(math.copysign(math.floor(abs(v) * 10**d + 0.5) / 10**d, v))


def _trunc(fr, a, k, w):
    d, v = _decimals(k, w), num(a[0], w)
    return f32(math.trunc(v * 10**d) / 10**d)


def _inverse(fn, name):
    def run(fr, a, k, w):
        v = num(a[0], w)
        if not -1 <= v <= 1:
            raise RunError(f"{w}: {name} of {v:g}: the value must be in -1..1")
        return f32(math.degrees(fn(v)))

    return run


def _pow(fr, a, k, w):
    base, exp = num(a[0], w), num(a[1], w)
    if base < 0 and exp != int(exp):
        raise RunError(f"{w}: Pow of a negative base with a fractional exponent")
    try:
        return f32(base**exp)
    except (OverflowError, ZeroDivisionError):
        raise RunError(f"{w}: Pow({base:g}, {exp:g}) has no value") from None


def _byte(value, w) -> int:
    b = num(value, w)
    if b != int(b) or not 0 <= b <= 255:
        raise RunError(f"{w}: {b:g} is not a byte (0..255)")
    return int(b)


def _str_part(fr, a, k, w):
    s = text(a[0], w)
    start = _position(a[1], w, len(s), "StrPart position")
    n = num(a[2], w)
    if n != int(n) or n < 0 or start - 1 + n > len(s):
        raise RunError(f"{w}: StrPart({len(s)} characters, {start}, {n:g}) reaches past the string's end")
    return s[start - 1 : start - 1 + int(n)]


def _str_find(fr, a, k, w):
    s, chars = text(a[0], w), text(a[2], w)
    start, outside = _position(a[1], w, len(s), "StrFind position"), "NOTINSET" in k
    for i in range(start - 1, len(s)):
        if (s[i] in chars) != outside:
            return f32(i + 1)
    return f32(len(s) + 1)


def _str_match(fr, a, k, w):
    s, pattern = text(a[0], w), text(a[2], w)
    found = s.find(pattern, _position(a[1], w, len(s), "StrMatch position") - 1)
    return f32(len(s) + 1 if found < 0 else found + 1)


def _str_memb(fr, a, k, w):
    s, chars = text(a[0], w), text(a[2], w)
    p = _position(a[1], w, len(s) - 1, "StrMemb position")
    return s[p - 1] in chars


def _str_order(fr, a, k, w):
    s1, s2, order = text(a[0], w), text(a[1], w), text(a[2], w)
    rank = {c: i for i, c in reversed(list(enumerate(order)))}
    key1 = [(rank.get(c, len(order)), c) for c in s1]
    key2 = [(rank.get(c, len(order)), c) for c in s2]
    return key1 <= key2


def _str_map(fr, a, k, w):
    s, src, dst = text(a[0], w), text(a[1], w), text(a[2], w)
    table = {}
    for i, c in enumerate(src):
        table.setdefault(c, dst[i] if i < len(dst) else c)
    return "".join(table.get(c, c) for c in s)


def _num_to_str(fr, a, k, w):
    v, d = num(a[0], w), num(a[1], w)
    if d != int(d) or not 0 <= d <= STRING_MAX:
        raise RunError(f"{w}: NumToStr decimals {d:g}: a string holds at most {STRING_MAX} characters")
    if "EXP" in k:
        s = f"{v:.{int(d)}E}"
        mantissa, exponent = s.split("E")
        return _string(f"{mantissa}E{int(exponent):+03d}", w)
    s = format_fixed(v, int(d))
    if len(s) > STRING_MAX:
        raise RunError(f"{w}: NumToStr result longer than {STRING_MAX} characters")
    return s


def _dim(fr, a, k, w):
    value, n = a[0], num(a[1], w)
    if not isinstance(value, list):
        raise RunError(f"{w}: Dim of a value that is not an array")
    for _ in range(int(n) - 1):
        if not value or not isinstance(value[0], list):
            raise RunError(f"{w}: Dim: the array has fewer than {n:g} dimensions")
        value = value[0]
    if n < 1 or n != int(n):
        raise RunError(f"{w}: Dim: dimension {n:g} (1, 2 or 3)")
    return f32(len(value))


def _pos2(a, w):
    return vec(rec(a[0], "POS", w), "XYZ"), vec(rec(a[1], "POS", w), "XYZ")


def _distance(fr, a, k, w):
    p, q = _pos2(a, w)
    return f32(math.dist(p, q))


def _dot(fr, a, k, w):
    p, q = _pos2(a, w)
    return f32(sum(x * y for x, y in zip(p, q, strict=True)))


def _magnitude(fr, a, k, w):
    return f32(math.hypot(*vec(rec(a[0], "POS", w), "XYZ")))


def _trig(fn):
    return lambda fr, a, k, w: f32(fn(math.radians(num(a[0], w))))


def _one(fn):
    return lambda fr, a, k, w: f32(fn(num(a[0], w)))


def _exp(v: float) -> float:
    try:
        return math.exp(v)
    except OverflowError:
        return math.inf


def _sqrt(fr, a, k, w):
    v = num(a[0], w)
    if v < 0:
        raise RunError(f"{w}: Sqrt of a negative number")
    return f32(math.sqrt(v))


def _bits(fn):
    return lambda fr, a, k, w: f32(fn(*(_byte(v, w) for v in a)) & 0xFF)


def _bit_shift(left: bool):
    def run(fr, a, k, w):
        value, n = _byte(a[0], w), num(a[1], w)
        if n != int(n) or not 0 <= n <= 8:
            raise RunError(f"{w}: a shift of {n:g} bits (0..8)")
        return f32(((value << int(n)) if left else (value >> int(n))) & 0xFF)

    return run


def _bit_check(fr, a, k, w):
    value, bit = _byte(a[0], w), num(a[1], w)
    if bit != int(bit) or not 1 <= bit <= 8:
        raise RunError(f"{w}: BitCheck bit {bit:g} (1..8)")
    return bool(value >> (int(bit) - 1) & 1)


TABLE = {
    "ABS": _one(abs),
    "SIN": _trig(math.sin),
    "COS": _trig(math.cos),
    "TAN": _trig(math.tan),
    "ACOS": _inverse(math.acos, "ACos"),
    "ASIN": _inverse(math.asin, "ASin"),
    "ATAN": lambda fr, a, k, w: f32(math.degrees(math.atan(num(a[0], w)))),
    "ATAN2": lambda fr, a, k, w: f32(math.degrees(math.atan2(num(a[0], w), num(a[1], w)))),
    "EXP": _one(_exp),
    "POW": _pow,
    "SQRT": _sqrt,
    "ROUND": _round,
    "TRUNC": _trunc,
    "DIM": _dim,
    "DISTANCE": _distance,
    "DOTPROD": _dot,
    "VECTMAGN": _magnitude,
    "BITAND": _bits(lambda x, y: x & y),
    "BITOR": _bits(lambda x, y: x | y),
    "BITXOR": _bits(lambda x, y: x ^ y),
    "BITNEG": _bits(lambda x: ~x),
    "BITLSH": _bit_shift(True),
    "BITRSH": _bit_shift(False),
    "BITCHECK": _bit_check,
    "STRLEN": lambda fr, a, k, w: f32(len(text(a[0], w))),
    "STRPART": _str_part,
    "STRFIND": _str_find,
    "STRMATCH": _str_match,
    "STRMEMB": _str_memb,
    "STRORDER": _str_order,
    "STRMAP": _str_map,
    "NUMTOSTR": _num_to_str,
    "VALTOSTR": lambda fr, a, k, w: _string(value_text(a[0]), w),
}
