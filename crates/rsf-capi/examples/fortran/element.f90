! A host code in Fortran calling rsf through iso_c_binding: the friction, state rate and
! slip-rate solve of the BP1-QD surface element, checked against closed forms; the cut-off
! form (QDYN's law 1) against its closed form written here; and the batch calls over an array
! of elements. Build (the test does this), with the module include/rsf.f90:
!   gfortran ../../include/rsf.f90 element.f90 ../../../../target/release/librsf_capi.a -lpthread -ldl -lm
program element
  use rsf
  implicit none
  type(RsfFrictionParams) :: fp, fps(3)
  type(RsfStateParams) :: sp, sps(3)
  real(c_double) :: psi, f, fx, fpsi, rate, lnv, lnth, tau, ss, lv(3), th(3), ta(3), sg(3), et(3)
  real(c_double) :: dpsi, v, theta, want, err_f, err_dv, err_dth, err_rate, bf(3), bx(3), bz(3), br(3)
  type(RsfFrictionParams) :: cp
  type(RsfStateParams) :: cs
  type(c_ptr) :: mesh
  real(c_double) :: mv(3), mth(3), mdv(3), mdth(3), mrate(3)
  integer(c_int) :: st, its, i, j
  real(c_double), parameter :: vp = 1d-9, sigma = 50d6, eta = 2670d0 * 3464d0 / 2d0
  fp = RsfFrictionParams(RSF_ABI_VERSION, RSF_FORM_REGULARIZED, 0.6d0, 0.010d0, 1d-6)
  sp = RsfStateParams(RSF_ABI_VERSION, RSF_LAW_AGING, 0.015d0, 0.008d0, 0d0)
  ! steady state at Vp: theta = Dc/Vp, friction = f0 + (a - b) ln(Vp/V0), d ln theta/dt = 0
  lnth = log(0.008d0 / vp)
  st = rsf_psi(sp, 1d-6, lnth, psi)
  st = rsf_friction(fp, log(vp), psi, f, fx, fpsi)
  ss = 0.6d0 + (0.010d0 - 0.015d0) * log(vp / 1d-6)
  st = rsf_ln_theta_rate(sp, log(vp), lnth, rate)
  print '(a,es12.4)', 'friction error ', abs(f - ss)
  print '(a,es12.4)', 'rate at steady state ', abs(rate)
  ! the slip rate balancing sigma f + eta Vp is Vp
  tau = sigma * f + eta * vp
  st = rsf_solve_slip_rate(fp, psi, tau, sigma, eta, log(vp) + 0.1d0, lnv, its)
  print '(a,es12.4,a,i0)', 'solve error ', abs(lnv - log(vp)), ' iterations ', its
  ! three elements at once
  do i = 1, 3
    fps(i) = fp
    sps(i) = sp
    th(i) = lnth
    sg(i) = sigma
    et(i) = eta
    ta(i) = tau * (1d0 + 1d-3 * i)
    lv(i) = log(vp)
  end do
  st = rsf_batch_solve_slip_rate(3_c_size_t, fps, sps, th, ta, sg, et, lv)
  print '(a,i0,a,3es12.4)', 'batch status ', st, ' V ', exp(lv)
  if (st /= RSF_OK .or. .not. (exp(lv(1)) > vp .and. exp(lv(3)) > exp(lv(2)))) stop 1

  ! the cut-off form: mu = f0 - a ln(V1/V + 1) + b ln(V2 theta/Dc + 1), dmu/dV = a V1/(V (V1 + V)),
  ! dmu/dtheta = b V2/(V2 theta + Dc), slip law dtheta/dt = -(V theta/Dc) ln(V theta/Dc);
  ! V1 travels in v0, V2 in the state's vc; largest relative errors over V and theta grids
  cp = RsfFrictionParams(RSF_ABI_VERSION, RSF_FORM_CUTOFF, 0.6d0, 0.001d0, 1d-3)
  cs = RsfStateParams(RSF_ABI_VERSION, RSF_LAW_SLIP, 0.0015d0, 1d-5, 1d-1)
  err_f = 0; err_dv = 0; err_dth = 0; err_rate = 0
  do i = -12, 1
    do j = -6, 3
      v = 10d0**i
      theta = 10d0**j
      st = rsf_state_term(cp, cs, log(theta), psi, dpsi)
      if (st /= RSF_OK) stop 2
      st = rsf_friction(cp, log(v), psi, f, fx, fpsi)
      if (st /= RSF_OK) stop 3
      want = 0.6d0 - 0.001d0 * log(1d-3 / v + 1d0) + 0.0015d0 * log(1d-1 * theta / 1d-5 + 1d0)
      err_f = max(err_f, abs(f - want))
      want = 0.001d0 * 1d-3 / v / (1d-3 + v)
      err_dv = max(err_dv, abs(fx / v - want) / want)
      want = 0.0015d0 * 1d-1 / (1d-1 * theta + 1d-5)
      err_dth = max(err_dth, abs(fpsi * dpsi / theta - want) / want)
      st = rsf_ln_theta_rate(cs, log(v), log(theta), rate)
      want = -(v * theta / 1d-5) * log(v * theta / 1d-5)
      ! (at V theta = Dc both are round-off around 0: compared where ln(V theta/Dc) is not)
      if (abs(log(v * theta / 1d-5)) > 1d-6) err_rate = max(err_rate, abs(theta * rate - want) / abs(want))
    end do
  end do
  print '(a,es12.4)', 'cutoff friction error ', err_f
  print '(a,es12.4)', 'cutoff dmu/dV error ', err_dv
  print '(a,es12.4)', 'cutoff dmu/dtheta error ', err_dth
  print '(a,es12.4)', 'slip rate error ', err_rate
  ! the batch partials over three elements of three forms equal the one-element calls
  fps(1) = fp
  fps(2) = RsfFrictionParams(RSF_ABI_VERSION, RSF_FORM_CLASSIC, 0.6d0, 0.010d0, 1d-6)
  fps(3) = cp
  sps(1) = sp
  sps(2) = sp
  sps(3) = cs
  lv = [log(1d-9), log(1d-3), log(1d-7)]
  th = [log(8d6), log(3d0), log(2d-4)]
  st = rsf_batch_partials(3_c_size_t, fps, sps, lv, th, bf, bx, bz, br)
  if (st /= RSF_OK) stop 4
  err_f = 0
  do i = 1, 3
    st = rsf_state_term(fps(i), sps(i), th(i), psi, dpsi)
    st = rsf_friction(fps(i), lv(i), psi, f, fx, fpsi)
    st = rsf_ln_theta_rate(sps(i), lv(i), th(i), rate)
    err_f = max(err_f, abs(bf(i) - f), abs(bx(i) - fx), abs(bz(i) - fpsi * dpsi), abs(br(i) - rate))
  end do
  print '(a,es12.4)', 'batch partials error ', err_f
  ! a Kato-Tullis state under the cut-off form is refused, and the message says why
  sps(3)%law = RSF_LAW_KATO_TULLIS
  st = rsf_batch_partials(3_c_size_t, fps, sps, lv, th, bf, bx, bz, br)
  print '(a,i0,a,a)', 'cutoff with kato-tullis -> ', st, ': ', rsf_error_message()
  ! a mesh of three classic elements, the third without healing (QDYN's itheta_law = 0):
  ! parameters checked once, then partials and rates in V and theta, as QDYN calls them
  sps(1) = RsfStateParams(RSF_ABI_VERSION, RSF_LAW_AGING, 0.015d0, 0.008d0, 0d0)
  sps(2) = sps(1)
  sps(3) = RsfStateParams(RSF_ABI_VERSION, RSF_LAW_AGING_NO_HEALING, 0.015d0, 0.008d0, 0d0)
  fps = fps(2)
  st = rsf_mesh_new(3_c_size_t, fps, sps, RSF_DOMAIN_CONTINUE, mesh)
  if (st /= RSF_OK) stop 5
  mv = [1d-9, -2d-10, 1d-3]
  mth = [8d6, 4d7, 3d0]
  st = rsf_mesh_partials(mesh, 3_c_size_t, mv, mth, mdv, mdth)
  if (st /= RSF_OK) stop 6
  st = rsf_mesh_state_rate(mesh, 3_c_size_t, mv, mth, mrate)
  if (st /= RSF_OK) stop 7
  err_f = 0
  do i = 1, 3
    err_f = max(err_f, abs(mdv(i) - 0.010d0 / mv(i)) / abs(mdv(i)), abs(mdth(i) - 0.015d0 / mth(i)) / abs(mdth(i)))
  end do
  err_rate = max(abs(mrate(1) - (1d0 - mv(1) * mth(1) / 0.008d0)), abs(mrate(2) - (1d0 - mv(2) * mth(2) / 0.008d0)), &
    abs(mrate(3) + mv(3) * mth(3) / 0.008d0))
  print '(a,es12.4)', 'mesh partials error ', err_f
  print '(a,es12.4)', 'mesh rate error ', err_rate
  call rsf_mesh_free(mesh)
end program
