# hrisim in a container: built on Debian 12 with the same package list and setup script as a
# developer machine, run as a non-root user. Inside the container the server binds 0.0.0.0, so it
# starts only with a token (HRISIM_TOKEN) or HRISIM_ALLOW_UNAUTHENTICATED=1.
FROM debian:12 AS build
WORKDIR /src
COPY scripts/setup scripts/debian-packages.txt scripts/
RUN ./scripts/setup && rm -rf /var/lib/apt/lists/*
COPY . .
RUN cmake --preset release && cmake --build --preset release && ./scripts/npm-deps web

FROM debian:12
COPY scripts/setup scripts/runtime-packages.txt /tmp/setup/
RUN /tmp/setup/setup /tmp/setup/runtime-packages.txt && rm -rf /var/lib/apt/lists/* /tmp/setup \
 && groupadd --system --gid 10001 hrisim \
 && useradd --system --uid 10001 --gid 10001 --create-home --home-dir /var/lib/hrisim hrisim
COPY --from=build /src/build/release/server/app/hrisim /usr/local/bin/hrisim
COPY --from=build /src/web/ /opt/hrisim/web/
COPY scenarios/ /opt/hrisim/scenarios/
ENV HRISIM_HOST=0.0.0.0 \
    HRISIM_PORT=8080 \
    HRISIM_DB=/var/lib/hrisim/hrisim.db \
    HRISIM_WEB_ROOT=/opt/hrisim/web \
    HRISIM_SCENARIOS=/opt/hrisim/scenarios
# By number, so that Kubernetes can check runAsNonRoot (deploy/kubernetes).
USER 10001:10001
WORKDIR /var/lib/hrisim
VOLUME /var/lib/hrisim
EXPOSE 8080
HEALTHCHECK --interval=30s --timeout=3s --start-period=5s CMD curl -fsS http://127.0.0.1:8080/healthz || exit 1
CMD ["hrisim", "serve"]
