% The time-domain milling simulation of toolpoint (include/toolpoint/stability/simulation.hpp), written
% out in GNU Octave / MATLAB for a side-by-side comparison of speed (docs/simulation.md,
% "Performance"): the same model and the same scheme, step for step, for straight teeth (one axial
% slice) and a linear force law, so that both give the same numbers.
%
%   Model: modes q'' + 2 zeta w q' + w^2 q = psi . F; r = sum psi q. The chip of tooth j at angle phi
%   (clockwise from +y; edge at R (sin phi, cos phi)): h = u.r + R + rho_j - max_q [u.r(t - T_q) +
%   R + rho_{j-q} - C_q sin phi] over the N teeth of the last revolution, u = (sin phi, cos phi);
%   F_t = a (K_te + K_t h), F_r = a (K_re + K_r K_t h) where h > 0 inside [phi_st, phi_ex];
%   F = F_t (-cos phi, sin phi) + F_r (-sin phi, -cos phi).
%   Scheme: exact modal propagator; the force linear over each cutting piece of a step (split at
%   the engagement's ends and at h = 0), its exact response (closed-form integrals); predicted with
%   the force held, corrected once.
%
% Run (from the repository): octave-cli --no-gui --quiet bench/octave/simulate_milling.m
% It prints the elapsed time of the simulation loop and the numbers that toolpoint's
% `simulate --revolutions 100 --steps 200` prints for the same case (bench/octave/compare.sh).

1;

function [p, j0, j1] = mode_step(w, zeta, h)
  % e^{A h} of (q, q') and the whole step's input integrals J0, J1 (see integrals below).
  wd = w * sqrt(1 - zeta^2);
  e = exp(-zeta * w * h); c = cos(wd * h); s = sin(wd * h);
  p = [e * (c + zeta * w / wd * s), e * s / wd; -e * w^2 / wd * s, e * (c - zeta * w / wd * s)];
  [j0, j1] = integrals(w, zeta, h, 0, h);
end

function [j0, j1] = integrals(w, zeta, h, alpha, beta)
  % Response over [alpha, beta] to a force linear from p_a to p_b: J0 p_a + J1 (p_b - p_a), with
  % lambda = -zeta w + i wd, K0 = (e^{lambda U1} - e^{lambda U0})/lambda,
  % K1 = (e^{lambda U1} - e^{lambda U0})/(lambda^2 L) - e^{lambda U0}/lambda, J = (Im K, Im lambda K)/wd.
  wd = w * sqrt(1 - zeta^2);
  lam = -zeta * w + 1i * wd;
  len = beta - alpha;
  e1 = exp(lam * (h - alpha)); e0 = exp(lam * (h - beta));
  k0 = (e1 - e0) / lam;
  k1 = (e1 - e0) / (lam^2 * len) - e0 / lam;
  j0 = [imag(k0); imag(lam * k0)] / wd;
  j1 = [imag(k1); imag(lam * k1)] / wd;
end

% ---- The case: the Insperger-Stepan mode (docs/reference.md section 7), rigid in y --------------------------
mass = 0.03993; zeta = 0.011; fn = 922;
psi = [1 / sqrt(mass); 0];              % an x mode
N = 2; D = 0.02; R = D / 2; rho = zeros(1, N);
Kt = 6e8; Kr = 2e8 / 6e8; Kte = 0; Kre = 0;
feed = 1e-4; depth = 2e-3; rpm = 10000;
st = acos(2 * 0.05 - 1); ex = pi;       % a/D 0.05, down-milling
revs = 100; m = 200;

tau = 60 / (N * rpm); h = tau / m; M = N * m; dphi = 2 * pi / M;
w = 2 * pi * fn;
[P, J0, J1] = mode_step(w, zeta, h);
offset = -(0:N-1) * m;                  % tooth j at -j pitches, in steps
ring_n = M + 2;
ring = repmat(R + rho', 1, ring_n);     % where each tooth passed, u.r + R + rho, last revolution
behind_tooth = zeros(N, N); behind_delay = zeros(N, N); behind_feed = zeros(N, N);
for j = 1:N
  for q = 1:N
    behind_tooth(j, q) = mod(j - 1 - q, N) + 1;
    behind_delay(j, q) = q * m;
    behind_feed(j, q) = N * feed * q / N;
  end
end

% The schedule of one revolution: per step and tooth the cutting piece [wa, wb] of the step.
wa = -ones(M, N); wb = -ones(M, N);
for s = 0:M-1
  for j = 1:N
    p0 = dphi * mod(s + offset(j), M);
    for shift = [0, 2 * pi]
      a = max(0, (st + shift - p0) / dphi); b = min(1, (ex + shift - p0) / dphi);
      if b > a + 1e-12
        wa(s + 1, j) = a; wb(s + 1, j) = b;
      end
    end
  end
end

total = revs * M;
first = floor(revs / 2) * M;            % the analysed revolutions: the last half
z = [0; 0];                             % (q, q')
rx = 0; ry = 0; px = 0; py = 0;         % displacement; the predictor's force
imp = [0; 0];
xrev = zeros(revs + 1, 1);
slot = 0;

tic;
for k = 0:total-1
  s = mod(k, M);
  zn = P * z;
  pf = psi' * [px; py];
  zp = zn + J0 * pf;
  rxp = psi(1) * zp(1); ryp = psi(2) * zp(1);
  ga = [0; 0]; gb = [0; 0]; endf = [0; 0];
  for j = 1:N
    if wa(s + 1, j) < 0, continue; end
    p0 = dphi * mod(s + offset(j), M);
    f = [wa(s + 1, j), wb(s + 1, j)];
    sn = sin(p0 + f * dphi); cs = cos(p0 + f * dphi);
    hh = zeros(1, 2);
    for e = 1:2
      x = rx + f(e) * (rxp - rx); y = ry + f(e) * (ryp - ry);
      wsurf = -inf;
      for q = 1:N
        g = f(e) - 0; base = slot - behind_delay(j, q);     % even pitch: whole steps
        if base < 0, base = base + ring_n; end
        pp = ring(behind_tooth(j, q), base + 1);
        if g > 0
          nxt = base + 1; if nxt == ring_n, nxt = 0; end
          pp = pp + g * (ring(behind_tooth(j, q), nxt + 1) - pp);
        end
        wsurf = max(wsurf, pp - sn(e) * behind_feed(j, q));
      end
      hh(e) = sn(e) * x + cs(e) * y + R + rho(j) - wsurf;
    end
    if hh(1) <= 0 && hh(2) <= 0, continue; end
    if hh(1) <= 0 || hh(2) <= 0
      fc = f(1) + (f(2) - f(1)) * hh(1) / (hh(1) - hh(2));
      if hh(1) > 0
        f(2) = fc; hh(2) = 0;
      else
        f(1) = fc; hh(1) = 0;
      end
      sn = sin(p0 + f * dphi); cs = cos(p0 + f * dphi);
      if ~(f(2) > f(1)), continue; end
    end
    ft = depth * (Kte + Kt * hh); fr = depth * (Kre + Kr * Kt * hh);
    F = [-ft .* cs - fr .* sn; ft .* sn - fr .* cs];    % columns: the piece's two ends
    if k >= first
      imp = imp + (f(2) - f(1)) * h * 0.5 * (F(:, 1) + F(:, 2));
    end
    if f(2) == 1, endf = endf + F(:, 2); end
    if f(1) == 0 && f(2) == 1
      ga = ga + F(:, 1); gb = gb + F(:, 2);
    else
      [a0, a1] = integrals(w, zeta, h, f(1) * h, f(2) * h);
      pa = psi' * F(:, 1); pb = psi' * F(:, 2);
      zn = zn + a0 * pa + a1 * (pb - pa);
    end
  end
  pa = psi' * ga; pb = psi' * gb;
  z = zn + J0 * pa + J1 * (pb - pa);
  rx = psi(1) * z(1); ry = psi(2) * z(1);
  px = endf(1); py = endf(2);
  slot = slot + 1; if slot == ring_n, slot = 0; end
  % Where each tooth passed at the step's end (near the engagement; elsewhere never read).
  for j = 1:N
    p1 = dphi * mod(s + 1 + offset(j), M);
    ring(j, slot + 1) = sin(p1) * rx + cos(p1) * ry + R + rho(j);
  end
  if mod(k + 1, M) == 0, xrev((k + 1) / M + 1) = rx; end
end
elapsed = toc;

t_an = (revs - floor(revs / 2)) * 60 / rpm;
printf('octave: %d steps in %.3f s (%.1f us per step)\n', total, elapsed, 1e6 * elapsed / total);
printf('mean_force_x_n %.12g\nmean_force_y_n %.12g\nlast_revolution_x_m %.12g\n', imp(1) / t_an, imp(2) / t_an, xrev(end));
