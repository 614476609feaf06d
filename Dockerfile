# isocorr on Debian 12, packages only. The build stage installs exactly the list that
# scripts/install-deps.sh installs in CI (deploy/packages.txt), through the same script.
FROM debian:12 AS build
WORKDIR /src
COPY deploy/packages.txt deploy/packages.txt
COPY scripts/install-deps.sh scripts/install-deps.sh
RUN ./scripts/install-deps.sh && rm -rf /var/lib/apt/lists/*
COPY . .
RUN cmake -S . -B /build -G Ninja -DCMAKE_BUILD_TYPE=Release -DISOCORR_BUILD_TESTS=OFF \
 && cmake --build /build -j "$(nproc)" \
 && cmake --install /build --prefix /opt/isocorr

FROM debian:12-slim
COPY deploy/runtime-packages.txt /tmp/runtime-packages.txt
RUN apt-get update \
 && grep -v '^\s*#' /tmp/runtime-packages.txt | grep -v '^\s*$' \
    | xargs apt-get install -y --no-install-recommends \
 && rm -rf /var/lib/apt/lists/* /tmp/runtime-packages.txt \
 && useradd --system --create-home --home-dir /var/lib/isocorr isocorr
COPY --from=build /opt/isocorr /opt/isocorr
ENV PATH=/opt/isocorr/bin:$PATH
USER isocorr
WORKDIR /var/lib/isocorr
ENTRYPOINT ["isocorr"]
CMD ["--help"]
