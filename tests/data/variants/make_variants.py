#!/usr/bin/env python3
"""Writes the small FRF files of tests/data/variants/ (see README.md there): each imitates how a
real program or script writes an FRF, and each holds the same closed-form single-degree-of-freedom
receptance so the tests can check every number read against the formula (computed again in C++).

    H(f) = 1 / (k - m w^2 + i c w),  w = 2 pi f,  m = 0.04 kg, fn = 1600 Hz, zeta = 0.02,
    k = m (2 pi fn)^2,  c = 2 zeta sqrt(k m);  f = 1000, 1200, ..., 2200 Hz (7 points).

Standard library only. Run from anywhere: python3 tests/data/variants/make_variants.py
"""
import cmath
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
M, FN, ZETA = 0.04, 1600.0, 0.02
K = M * (2 * math.pi * FN) ** 2
C = 2 * ZETA * math.sqrt(K * M)
FREQS = [1000.0 + 200.0 * i for i in range(7)]
G = 9.80665


def h(f):
    w = 2 * math.pi * f
    return 1.0 / complex(K - M * w * w, C * w)


def write(name, data, binary=False):
    with open(os.path.join(HERE, name), 'wb') as fh:
        fh.write(data if binary else data.encode('utf-8'))


# ---- CSV ---------------------------------------------------------------------------------------

def de(x):
    """A number with a decimal comma, 15 significant digits after the point."""
    return ('%.15e' % x).replace('.', ',')


rows = ['"Frequency [Hz]";"Real [m/N]";"Imaginary [m/N]"']
rows += ['%s;%s;%s' % (de(f), de(h(f).real), de(h(f).imag)) for f in FREQS]
write('csv_de_locale_semicolon_decimal_comma.csv', '\ufeff' + '\r\n'.join(rows) + '\r\n')


def coherence(f):  # a plausible coherence, low at the antiresonance-free band edges
    return 0.9 + 0.09 * math.sin(f / 300.0)


rows = ['Freq (Hz)\tMagnitude (m/N)\tPhase (deg)\tCoherence']
rows.append('0\t0\t0\t0')  # the DC line of an FFT: dropped with a warning
rows += ['%.17g\t%.17g\t%.17g\t%.17g' % (f, abs(h(f)), math.degrees(cmath.phase(h(f))), coherence(f)) for f in FREQS]
write('csv_tab_mag_phase_deg_coherence.csv', '\n'.join(rows) + '\n')

rows = ['Frequency/Hz,Magnitude [dB re 1 m/N],Phase [rad]']
rows += ['%.17g,%.17g,%.17g' % (f, 20 * math.log10(abs(h(f))), cmath.phase(h(f))) for f in FREQS]
write('csv_bode_db_phase_rad.csv', '\n'.join(rows) + '\n')

rows = ['f_Hz,Re [mm/s/N],Im [mm/s/N]']
for f in FREQS:
    y = 1j * 2 * math.pi * f * h(f) * 1000.0
    rows.append('%.17g,%.17g,%.17g' % (f, y.real, y.imag))
write('csv_mobility_mm_per_s.csv', '\n'.join(rows) + '\n')

rows = ['Frequency (Hz),Real (g/N),Imag (g/N),Coherence']
for f in FREQS:
    a = -(2 * math.pi * f) ** 2 * h(f) / G
    rows.append('%.17g,%.17g,%.17g,%.17g' % (f, a.real, a.imag, coherence(f)))
write('csv_accelerance_g.csv', '\n'.join(rows) + '\n')

rows = ['# written by numpy.savetxt(..., header=..., delimiter=",")', '# tap test, point 1, 5 averages',
        'freq,re,im,coh,channel']
rows += ['%.18e,%.18e,%.18e,%.18e,%.18e' % (f, h(f).real, h(f).imag, coherence(f), 3) for f in FREQS]
write('csv_numpy_extra_column.csv', '\n'.join(rows) + '\n')

rows = ['Freq,Mag,Phase'] + ['%.17g,%.17g,%.17g' % (f, abs(h(f)), math.degrees(cmath.phase(h(f)))) for f in FREQS]
write('csv_phase_without_unit.csv', '\n'.join(rows) + '\n')

rows = ['%.17g,%.17g,%.17g' % (f, h(f).real, h(f).imag) for f in FREQS]
write('csv_no_header.csv', '\n'.join(rows) + '\n')

# ---- CutPro .frf -------------------------------------------------------------------------------

# The layout of the MATLAB script that writes FRFs for CutPro (Matlab2CutPro): the first data line
# carries the labels after its numbers, every line ends with a tab.
lines = ['%14.6e\t%14.12e\t%14.12e\tFreq\tHz\tReal\tm/N\tImag\tReal\t' % (FREQS[0], h(FREQS[0]).real, h(FREQS[0]).imag)]
lines += ['%14.6e\t%14.12e\t%14.12e\t' % (f, h(f).real, h(f).imag) for f in FREQS[1:]]
write('frf_cutpro_labels_on_first_line.frf', '\n'.join(lines) + '\n')

lines = ['Freq\tHz\tReal\tm/N\tImag\tm/N'] + ['%.17g\t%.17g\t%.17g' % (f, h(f).real, h(f).imag) for f in FREQS]
write('frf_cutpro_labels_own_line.frf', '\r\n'.join(lines) + '\r\n')

lines = ['Frequency\tMagnitude\tPhase'] + ['%.17g\t%.17g\t%.17g' % (f, abs(h(f)), math.degrees(cmath.phase(h(f))))
                                         for f in FREQS]
write('frf_mag_phase_renamed.frf', '\n'.join(lines) + '\n')
write('frf_mag_phase_renamed_no_header.frf', '\n'.join(lines[1:]) + '\n')

# ---- UFF 58 ------------------------------------------------------------------------------------

def records(id1, num_pts, ord_type, spacing, xmin, dx, num_type=8, num_units='m', den_units='N', node=1):
    """Records 1-11 as pyuff's _write58 formats them."""
    out = ['%-80s' % id1, '%-80s' % 'NONE', '%-80s' % 'NONE', '%-80s' % 'NONE', '%-80s' % 'NONE']
    out.append('%5i%10i%5i%10i %10s%10i%4i %10s%10i%4i' % (4, 0, 0, 0, 'NONE', node, 3, 'NONE', 1, 3))
    out.append('%10i%10i%10i%13.5e%13.5e%13.5e' % (ord_type, num_pts, spacing, xmin, dx, 0.0))
    out.append('%10i%5i%5i%5i %-20s %-20s' % (18, 0, 0, 0, 'Frequency', 'Hz'))
    out.append('%10i%5i%5i%5i %-20s %-20s' % (num_type, 0, 0, 0, 'Response', num_units))
    out.append('%10i%5i%5i%5i %-20s %-20s' % (13, 0, 0, 0, 'Force', den_units))
    out.append('%10i%5i%5i%5i %-20s %-20s' % (0, 0, 0, 0, 'NONE', 'NONE'))
    return out


def even_binary_values(values):
    data = b''
    for v in values:
        data += struct.pack('<d', v.real) + struct.pack('<d', v.imag)
    return data


# pyuff 2.x, binary=1, complex data: the header's byte count is num_pts * 8, half the bytes written.
n = len(FREQS)
head = '    -1\n    58b%6i%6i%12i%12i%6i%6i%12i%12i\n' % (1, 2, 11, n * 8, 0, 0, 0, 0)
head += '\n'.join(records('pyuff complex double, binary', n, 6, 1, FREQS[0], 200.0)) + '\n'
write('uff_pyuff_58b_half_byte_count.uff',
      head.encode() + even_binary_values([h(f) for f in FREQS]) + b'    -1\n', binary=True)

# CRLF line ends and a stray CRLF before and after the binary block.
head = '    -1\r\n    58b%6i%6i%12i%12i%6i%6i%12i%12i\r\n' % (1, 2, 11, n * 16, 0, 0, 0, 0)
head += '\r\n'.join(records('CRLF around the binary block', n, 6, 1, FREQS[0], 200.0)) + '\r\n'
write('uff_58b_crlf_around_binary.uff',
      head.encode() + b'\r\n' + even_binary_values([h(f) for f in FREQS]) + b'\r\n    -1\r\n', binary=True)


def fortran_d(x):
    """E20.12 with a D exponent letter, as Fortran's D format writes."""
    return ('%20.12E' % x).replace('E', 'D')


vals = []
for f in FREQS:
    vals += [h(f).real, h(f).imag]
lines = ['    -1', '    58'] + records('Fortran D exponents', n, 6, 1, FREQS[0], 200.0)
for i in range(0, len(vals), 4):
    lines.append(''.join(fortran_d(v) for v in vals[i:i + 4]))
lines.append('    -1')
write('uff_fortran_d_exponents.uff', '\n'.join(lines) + '\n')

# A writer that prints E13.6 into the 13-column fields of 6E13.5 (complex single): negative
# numbers fill the field, so neighbours run together ("-1.234567E-06-2.345678E-07").
lines = ['    -1', '    58'] + records('E13.6 in 13 columns', n, 5, 1, FREQS[0], 200.0)
for i in range(0, len(vals), 6):
    lines.append(''.join('%13.6E' % v for v in vals[i:i + 6]))
lines.append('    -1')
write('uff_run_together_fields.uff', '\n'.join(lines) + '\n')

# A file cut in the middle of its last number (a copy interrupted, a disk full).
lines = ['    -1', '    58'] + records('cut short', n, 6, 1, FREQS[0], 200.0)
for i in range(0, len(vals), 4):
    lines.append(''.join('%20.12E' % v for v in vals[i:i + 4]))
text = '\n'.join(lines)
write('uff_truncated_mid_number.uff', text[:-4])  # '-1.234567890123E-0' of '…E-07'

# One data field of 90 characters: 1e-6 written as 0.000…01E+75 (a writer printing in F format
# with a huge exponent; the fuzz finding): it must be read as exactly that number.
long_field = '0.' + '0' * 80 + '1E+75'
assert float(long_field) == 1e-06
lines = ['    -1', '    58'] + records('long numeric field', 1, 6, 1, 1000.0, 200.0)
lines.append(long_field + ' -1.0E-6')
lines.append('    -1')
write('uff_long_numeric_field.uff', '\n'.join(lines) + '\n')

# An ID line of 95 characters, as some exporters write (the format holds 80).
lines = ['    -1', '    58'] + records('x' * 95, n, 6, 1, FREQS[0], 200.0)
for i in range(0, len(vals), 4):
    lines.append(''.join('%20.12E' % v for v in vals[i:i + 4]))
lines.append('    -1')
text = '\n'.join(lines).replace('x' * 95 + ' ' * 0, 'x' * 95) + '\n'
write('uff_long_id_line.uff', text)

# Accelerance in g/N: record 9 acceleration (12) in 'g', record 10 force (13) in 'N', as
# accelerometer channels calibrated in g export.
accel = [-(2 * math.pi * f) ** 2 * h(f) / G for f in FREQS]
avals = []
for a in accel:
    avals += [a.real, a.imag]
lines = ['    -1', '    58'] + records('accelerance in g/N', n, 6, 1, FREQS[0], 200.0, num_type=12, num_units='g')
for i in range(0, len(avals), 4):
    lines.append(''.join('%20.12E' % v for v in avals[i:i + 4]))
lines.append('    -1')
write('uff_accelerance_g_per_N.uff', '\n'.join(lines) + '\n')
