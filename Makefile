# Installs rsf's C ABI for hosts in C, C++ and Fortran (docs/faultsim.md#installing):
#
#   make install PREFIX=/opt/rsf        # builds with cargo once, then copies
#   make install PREFIX=$HOME/.local DESTDIR=/tmp/stage
#   make uninstall PREFIX=/opt/rsf
#   make install-files PREFIX=/opt/rsf LIB=DIR   # copies a library already built in DIR
#
# Installed: lib/librsf_capi.{a,so}, include/rsf.h, include/rsf.f90 (the Fortran module's
# source), lib/pkgconfig/rsf.pc and lib/cmake/rsf/rsfConfig{,Version}.cmake. After that, a
# host's build needs neither Rust nor this checkout: pkg-config --cflags --libs rsf, or
# find_package(rsf CONFIG) and rsf::rsf / rsf::rsf_static.
#
# Everything else here is cargo's (README.md).

PREFIX ?= /usr/local
DESTDIR ?=
CARGO ?= cargo
# the library's build folder (cargo's --target-dir; default target/)
TARGET_DIR ?= target
VERSION := $(shell sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -1)
MAJOR := $(word 1,$(subst ., ,$(VERSION)))
MINOR := $(word 2,$(subst ., ,$(VERSION)))
LIB := $(TARGET_DIR)/release
DEST := $(DESTDIR)$(PREFIX)
CAPI := crates/rsf-capi

.PHONY: install install-files uninstall capi

capi:
	$(CARGO) build --release -p rsf-capi --target-dir $(TARGET_DIR)

install: capi
	$(MAKE) --no-print-directory install-files PREFIX=$(PREFIX) DESTDIR=$(DESTDIR) LIB=$(LIB)

install-files:
	install -d $(DEST)/lib/pkgconfig $(DEST)/lib/cmake/rsf $(DEST)/include
	install -m 644 $(LIB)/librsf_capi.a $(DEST)/lib/librsf_capi.a
	install -m 755 $(LIB)/librsf_capi.so $(DEST)/lib/librsf_capi.so
	install -m 644 $(CAPI)/include/rsf.h $(CAPI)/include/rsf.f90 $(DEST)/include/
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@VERSION@|$(VERSION)|' $(CAPI)/install/rsf.pc.in > $(DEST)/lib/pkgconfig/rsf.pc
	install -m 644 $(CAPI)/install/rsfConfig.cmake $(DEST)/lib/cmake/rsf/rsfConfig.cmake
	sed -e 's|@VERSION@|$(VERSION)|g' -e 's|@MAJOR@|$(MAJOR)|g' -e 's|@MINOR@|$(MINOR)|g' \
		$(CAPI)/install/rsfConfigVersion.cmake.in > $(DEST)/lib/cmake/rsf/rsfConfigVersion.cmake
	@echo "installed rsf $(VERSION) under $(DEST): pkg-config --cflags --libs rsf (PKG_CONFIG_PATH=$(PREFIX)/lib/pkgconfig), or find_package(rsf CONFIG) (CMAKE_PREFIX_PATH=$(PREFIX))"

uninstall:
	rm -f $(DEST)/lib/librsf_capi.a $(DEST)/lib/librsf_capi.so $(DEST)/include/rsf.h $(DEST)/include/rsf.f90 \
		$(DEST)/lib/pkgconfig/rsf.pc $(DEST)/lib/cmake/rsf/rsfConfig.cmake $(DEST)/lib/cmake/rsf/rsfConfigVersion.cmake
	-rmdir $(DEST)/lib/cmake/rsf 2> /dev/null
