#!/usr/bin/env python3
"""Writes the committed seed inputs of the `diagram_stream` fuzz target:
the second round of hostile input (issue 29) in small copies. Each seed's
first two bytes pick the option combination (tests/src/fuzz.rs, `options`
and `options2`); the rest is the file. Deterministic; run from this folder:
    python3 make_seeds.py
Copy them into the corpus before a run: cp seeds/diagram_stream/* corpus/diagram_stream/
"""
import codecs, math, os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "diagram_stream")
os.makedirs(OUT, exist_ok=True)


def p_bar(a):
    d = (a - 10 + 360) % 720 - 360
    return 1.0 + 50.0 * math.exp(-((d / 30.0) ** 2))


ROWS = [f"{a / 2:g},{p_bar(a / 2):.4f}" for a in range(0, 1440, 8)]  # 4° steps
BODY = "crank_deg,pressure_bar\n" + "\n".join(ROWS) + "\n"


def seed(name, data, pick=0, more=0):
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(bytes([pick, more]) + data)


for i, tok in enumerate(["4.9e3", "1e308", "1e-300", "4,900", "-4900", "nan", "4 900", "4'900", "0", "4,9"]):
    seed(f"banner_{i}", f"----Engine speed[rpm] = {tok}    Load[%] = 100.0----\n" + BODY)
seed("rpm_line_exponent", "# rpm = 4.9e3\n" + BODY)
u16 = codecs.BOM_UTF16_LE + BODY.encode("utf-16-le")
seed("utf16_cut_mid_character", u16[:-3])
seed("utf16_mark_over_8bit", codecs.BOM_UTF16_LE + BODY.encode())
lines = BODY.split("\n")
lines[30] += "\0"
seed("nul_line_31", "\n".join(lines))
seed("half_cycle", "crank_deg,pressure_bar\n" + "\n".join(ROWS[:87]) + "\n", more=32)
seed("columns_too_many", "\n".join(r + ",1" * 9 for r in ROWS) + "\n", pick=8 | 64)
seed("huge_absolute", "crank_deg,pressure_bar\n" + "\n".join(f"{r.split(',')[0]},{float(r.split(',')[1]) * 2000}" for r in ROWS) + "\n")


def record(fast_pulse, with_pulse=True):
    out = ["time_s,pressure_v" + (",tdc" if with_pulse else "")]
    per_deg = 1.0 / (1500 * 6.0)
    for k in range(0, 4 * 180):
        a = k * 4.0
        pulse = k % 2 if fast_pulse else int(a % 360 < 5)
        row = f"{a * per_deg:.7f},{p_bar(a % 720) / 20:.4f}"
        out.append(row + (f",{pulse}" if with_pulse else ""))
    return "\n".join(out) + "\n"


seed("record_pulse", record(False), pick=16)
seed("record_pulse_rpm_contradicts", record(False), pick=16, more=1)
seed("record_fast_pulse", record(True), pick=16, more=1)
seed("record_gain_1e6", record(False), pick=16, more=4)
seed("record_clock_tdc_time_beyond", record(False, with_pulse=False), pick=128, more=2)


# Spreadsheets (issue 29, items 2-4), small copies built from the committed
# fixture `excel_single.xlsx`: empty rows past the 10,000 bound after the
# diagram, an error cell, a formula never calculated, and damaged bytes.
import io, zipfile

FIXTURES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "fixtures", "measured")


def xlsx_with(sheet_edit):
    src = zipfile.ZipFile(os.path.join(FIXTURES, "excel_single.xlsx"))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for info in src.infolist():
            data = src.read(info.filename)
            if info.filename == "xl/worksheets/sheet1.xml":
                data = sheet_edit(data.decode()).encode()
            z.writestr(info.filename, data)
    return out.getvalue()


seed("xlsx_empty_rows_bomb", xlsx_with(lambda s: s.replace("</sheetData>", "<row/>" * 20000 + "</sheetData>")))
seed("xlsx_error_cell", xlsx_with(lambda s: s.replace('<c r="B3" t="n"><v>', '<c r="B3" t="e"><v>#DIV/0!</v></c><c r="Z3" t="n"><v>', 1)))
seed("xlsx_formula_never_calculated", xlsx_with(lambda s: s.replace('<c r="B4" t="n"><v>', '<c r="B4"><f>B3*2</f></c><c r="Z4" t="n"><v>', 1)))
whole = xlsx_with(lambda s: s)
seed("xlsx_cut", whole[: len(whole) // 2])
xls = open(os.path.join(FIXTURES, "libreoffice_cycles.xls"), "rb").read()
seed("xls_damaged_fat", xls[:76] + b"\xff" * 8 + xls[84:])
